// A 3D landmark: position, representative descriptor, viewing direction and the distance range
// over which its ORB scale can be seen, plus the keyframes that observe it.
// All map objects are guarded by the one Map mutex (Map::mutex()).
#pragma once

#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <map>
#include <memory>

#include "smap/features/FeatureSet.h"

namespace smap::slam
{
class KeyFrame;

class MapPoint
{
public:
    struct Observation
    {
        KeyFrame* keyframe = nullptr;
        size_t index = 0;  ///< keypoint index in that keyframe
    };

    MapPoint(uint64_t id, const Eigen::Vector3d& position_world, KeyFrame* reference);

    uint64_t id() const { return id_; }
    uint64_t firstKeyFrameId() const { return firstKeyFrameId_; }
    Eigen::Vector3d position_world;
    std::array<uint8_t, 32> descriptor{};

    /// Observations by keyframe id (ordered, so every traversal is deterministic).
    const std::map<uint64_t, Observation>& observations() const { return observations_; }
    size_t numObservations() const { return observations_.size(); }
    void addObservation(KeyFrame* kf, size_t index);
    /// Removes kf's observation; a point left with fewer than 2 becomes bad.
    void eraseObservation(KeyFrame* kf);
    bool isObservedBy(const KeyFrame* kf) const;

    /// Marks the point bad and removes it from every observing keyframe.
    void setBad();
    bool isBad() const { return bad_; }
    /// Moves every observation to `other` and marks this point bad (duplicate fusion).
    void replaceWith(const std::shared_ptr<MapPoint>& other);
    std::shared_ptr<MapPoint> replacement() const { return replacedBy_; }

    /// Mean viewing direction and the distance range [min, max] in which it can be seen.
    void updateNormalAndDepth();
    /// The observation descriptor with the least median distance to the others.
    void computeDistinctiveDescriptor();
    Eigen::Vector3d normal() const { return normal_; }
    double minDistance() const { return 0.8 * minDistance_; }
    double maxDistance() const { return 1.2 * maxDistance_; }
    /// Pyramid level at which the point should appear at `distance`.
    int predictLevel(double distance, const features::ScalePyramid& pyramid) const;

    void increaseVisible(int n = 1) { visible_ += n; }
    void increaseFound(int n = 1) { found_ += n; }
    double foundRatio() const { return static_cast<double>(found_) / visible_; }

    /// The tracker's mark for one local-map search (numbered from 1; tracking thread only):
    /// true the first time it is called with `search`, false after, so a point seen by many
    /// local keyframes is taken once.
    bool markForSearch(uint64_t search)
    {
        if (searchMark_ == search)
            return false;
        searchMark_ = search;
        return true;
    }

private:
    uint64_t id_;
    uint64_t firstKeyFrameId_;
    KeyFrame* reference_;
    std::map<uint64_t, Observation> observations_;
    Eigen::Vector3d normal_ = Eigen::Vector3d::Zero();
    double minDistance_ = 0.0, maxDistance_ = 0.0;
    int visible_ = 1, found_ = 1;
    uint64_t searchMark_ = 0;
    bool bad_ = false;
    std::shared_ptr<MapPoint> replacedBy_;
};
}  // namespace smap::slam
