#include "smap/slam/KeyFrameDatabase.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "smap/features/DescriptorMatcher.h"

namespace smap::slam
{
namespace
{
cv::Mat selectRows(const cv::Mat& descriptors, const std::vector<size_t>& rows)
{
    if (descriptors.type() != CV_8UC1 || descriptors.cols != 32)
        throw std::invalid_argument(
            "KeyFrameDatabase: descriptors must be CV_8UC1 with 32 columns");
    cv::Mat out(static_cast<int>(rows.size()), 32, CV_8UC1);
    for (size_t k = 0; k < rows.size(); ++k)
        descriptors.row(static_cast<int>(rows[k])).copyTo(out.row(static_cast<int>(k)));
    return out;
}
}  // namespace

KeyFrameDatabase::ChunkLists KeyFrameDatabase::chunkLists(const cv::Mat& descriptors)
{
    ChunkLists lists;
    const int n = std::min(descriptors.rows, 0xffff);
    for (auto& l : lists)
        l.reserve(static_cast<size_t>(n));
    for (int r = 0; r < n; ++r)
    {
        const uint8_t* d = descriptors.ptr<uint8_t>(r);
        for (int c = 0; c < kChunks; ++c)
        {
            const uint32_t value = static_cast<uint32_t>(d[2 * c]) << 8U | d[2 * c + 1];
            lists[static_cast<size_t>(c)].push_back(value << 16U | static_cast<uint32_t>(r));
        }
    }
    for (auto& l : lists)
        std::sort(l.begin(), l.end());
    return lists;
}

void KeyFrameDatabase::add(uint64_t keyframeId, const cv::Mat& descriptors,
                           const std::vector<size_t>& rows)
{
    Entry e;
    e.descriptors = selectRows(descriptors, rows);
    e.chunks = chunkLists(e.descriptors);
    entries_[keyframeId] = std::move(e);
}

void KeyFrameDatabase::erase(uint64_t keyframeId)
{
    entries_.erase(keyframeId);
}

std::vector<uint64_t> KeyFrameDatabase::ids() const
{
    std::vector<uint64_t> out;
    out.reserve(entries_.size());
    for (const auto& [id, e] : entries_)
        out.push_back(id);
    return out;
}

std::vector<char> KeyFrameDatabase::matchedRows(const Entry& query, const Entry& entry,
                                                int max_distance)
{
    std::vector<char> found(static_cast<size_t>(query.descriptors.rows), 0);
    for (size_t c = 0; c < kChunks; ++c)
    {
        const auto& a = query.chunks[c];
        const auto& b = entry.chunks[c];
        size_t i = 0, j = 0;
        while (i < a.size() && j < b.size())
        {
            const uint32_t va = a[i] >> 16U, vb = b[j] >> 16U;
            if (va < vb)
                ++i;
            else if (vb < va)
                ++j;
            else
            {
                // Every pair of the two runs with this chunk value.
                size_t jEnd = j;
                while (jEnd < b.size() && (b[jEnd] >> 16U) == va)
                    ++jEnd;
                for (; i < a.size() && (a[i] >> 16U) == va; ++i)
                {
                    const uint32_t qa = a[i] & 0xffffU;
                    if (found[qa])
                        continue;
                    for (size_t k = j; k < jEnd; ++k)
                    {
                        const uint32_t rb = b[k] & 0xffffU;
                        if (features::descriptorDistance(
                                query.descriptors.ptr<uint8_t>(static_cast<int>(qa)),
                                entry.descriptors.ptr<uint8_t>(static_cast<int>(rb))) <=
                            max_distance)
                        {
                            found[qa] = 1;
                            break;
                        }
                    }
                }
                j = jEnd;
            }
        }
    }
    return found;
}

std::vector<KeyFrameDatabase::Score> KeyFrameDatabase::query(
    const cv::Mat& descriptors, const std::vector<size_t>& rows, int max_distance, int min_matches,
    const std::set<uint64_t>& exclude) const
{
    Entry q;
    q.descriptors = selectRows(descriptors, rows);
    q.chunks = chunkLists(q.descriptors);
    std::vector<std::pair<uint64_t, std::vector<char>>> found;
    std::vector<int> holders(rows.size(), 0);  // keyframes holding a copy, per query row
    for (const auto& [id, e] : entries_)
    {
        found.emplace_back(id, matchedRows(q, e, max_distance));
        for (size_t r = 0; r < rows.size(); ++r)
            holders[r] += found.back().second[r];
    }
    const double n = static_cast<double>(entries_.size());
    std::vector<Score> out;
    for (const auto& [id, rowsFound] : found)
    {
        if (exclude.count(id))
            continue;
        Score s{id, 0, 0.0};
        for (size_t r = 0; r < rows.size(); ++r)
            if (rowsFound[r])
            {
                s.matches++;
                s.score += std::log(n / holders[r]);
            }
        if (s.matches >= min_matches)
            out.push_back(s);
    }
    std::stable_sort(out.begin(), out.end(),
                     [](const Score& a, const Score& b) { return a.score > b.score; });
    return out;
}
}  // namespace smap::slam
