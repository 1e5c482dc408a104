// Place recognition without a vocabulary (none can be downloaded): every keyframe's ORB
// descriptors, indexed by their sixteen 16-bit chunks. Two descriptors within a small Hamming
// distance almost always share one chunk exactly (two within 15 bits always do, by the
// pigeonhole principle; two within 40 bits do with probability above 0.8), so a query compares
// only the descriptors that share a chunk with it and then checks their full distance. A
// keyframe's score sums, over the query descriptors it holds a near copy of, how rare each is
// among the keyframes (log(N / n), n of the N keyframes hold a copy: tf-idf without words), so
// that a pattern every keyframe shows (a repeated texture) counts for little.
#pragma once

#include <array>
#include <cstdint>
#include <map>
#include <opencv2/core/mat.hpp>
#include <set>
#include <vector>

namespace smap::slam
{
class KeyFrameDatabase
{
public:
    struct Score
    {
        uint64_t keyframeId = 0;
        int matches = 0;     ///< query descriptors with a copy within the distance in the keyframe
        double score = 0.0;  ///< those descriptors weighted by their rarity
    };

    /// Indexes `rows` of `descriptors` (CV_8UC1, 32 bytes a row) under `keyframeId`, replacing
    /// what that id held.
    void add(uint64_t keyframeId, const cv::Mat& descriptors, const std::vector<size_t>& rows);
    void erase(uint64_t keyframeId);
    size_t size() const { return entries_.size(); }
    bool contains(uint64_t keyframeId) const { return entries_.count(keyframeId) > 0; }
    /// The indexed keyframes' ids, increasing.
    std::vector<uint64_t> ids() const;

    /// Every indexed keyframe not in `exclude` with at least `min_matches` matches against
    /// `rows` of `descriptors` (a descriptor counts once per keyframe when one of the
    /// keyframe's is within `max_distance` bits), highest score first, ties by id. The rarity
    /// weights count every indexed keyframe, excluded ones too.
    std::vector<Score> query(const cv::Mat& descriptors, const std::vector<size_t>& rows,
                             int max_distance, int min_matches,
                             const std::set<uint64_t>& exclude = {}) const;

private:
    static constexpr int kChunks = 16;
    /// One sorted list per chunk of (chunk value << 16 | local row).
    using ChunkLists = std::array<std::vector<uint32_t>, kChunks>;
    struct Entry
    {
        cv::Mat descriptors;  ///< the indexed rows only, in order
        ChunkLists chunks;
    };
    static ChunkLists chunkLists(const cv::Mat& descriptors);
    /// 1 for each query row with a copy in `entry`.
    static std::vector<char> matchedRows(const Entry& query, const Entry& entry, int max_distance);

    std::map<uint64_t, Entry> entries_;
};
}  // namespace smap::slam
