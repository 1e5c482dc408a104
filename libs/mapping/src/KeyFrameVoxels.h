// Which keyframes put a point in each voxel, and over what time: the confirmation test of
// points near movers (SemanticMapBuilder, [map] confirm_near_movers). Private to libs/mapping.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <limits>
#include <unordered_map>
#include <vector>

namespace smap::mapping
{
/// One hash key for voxel indices (x, y, z): 21 bits each, +-1 million voxels per axis.
inline int64_t voxelKey(int64_t x, int64_t y, int64_t z)
{
    constexpr int64_t kMask = (1 << 21) - 1;
    return ((x & kMask) << 42) | ((y & kMask) << 21) | (z & kMask);
}

class KeyFrameVoxels
{
public:
    /// `edge`: the voxel size (m); `needed`: keyframes that confirm; `span_s`: time (s) they
    /// must span at least (first to last); `needClear`: one of them must have seen the place clear,
    /// with its own point within `edge` of the point confirmed.
    KeyFrameVoxels(double edge, size_t needed, double span_s, bool needClear);

    /// Keyframe number `keyframe`, made at `time` (s), put a point at p; `clear`: none of
    /// that keyframe's own movers was near p.
    void add(const Eigen::Vector3f& p, uint32_t keyframe, double time, bool clear);
    /// At least `needed` distinct keyframes in the 27 voxels around p, spanning `span_s`,
    /// and (with `needClear`) a point within `edge` of p put by a keyframe that saw it clear:
    /// the clear view must be of the same surface, not of a static point up to two voxels
    /// away that confirms nothing at p (a person's missed parts seen twice stay unconfirmed).
    bool confirmed(const Eigen::Vector3f& p) const;

private:
    struct Seen
    {
        std::vector<uint32_t> keyframes;  ///< distinct, at most `needed_`
        double firstTime = std::numeric_limits<double>::infinity();
        double lastTime = -std::numeric_limits<double>::infinity();
        /// Points put here by keyframes with no mover of their own near, thinned: none within
        /// edge / 4 of another (on a surface, a few dozen per voxel at most). The thinning
        /// makes "within `edge`" exact to edge / 4.
        std::vector<Eigen::Vector3f> clearPoints;
    };
    int64_t cell(float a) const;

    double edge_;
    size_t needed_;
    double span_s_;
    bool needClear_;
    std::unordered_map<int64_t, Seen> seen_;
};
}  // namespace smap::mapping
