#include "smap/features/DescriptorMatcher.h"

#include <limits>
#include <numeric>

namespace smap::features
{
std::vector<DescriptorMatch> matchWithRatioTest(const cv::Mat& query, const cv::Mat& train,
                                                float ratio, int max_distance,
                                                const std::vector<size_t>& query_rows,
                                                const std::vector<size_t>& train_rows)
{
    std::vector<size_t> qs = query_rows, ts = train_rows;
    if (qs.empty())
    {
        qs.resize(static_cast<size_t>(query.rows));
        std::iota(qs.begin(), qs.end(), size_t{0});
    }
    if (ts.empty())
    {
        ts.resize(static_cast<size_t>(train.rows));
        std::iota(ts.begin(), ts.end(), size_t{0});
    }
    // Best query per train row, so that a train row is never matched twice.
    std::vector<DescriptorMatch> bestForTrain(static_cast<size_t>(train.rows),
                                              {0, 0, std::numeric_limits<int>::max()});
    for (size_t q : qs)
    {
        const uint8_t* dq = query.ptr<uint8_t>(static_cast<int>(q));
        int best = std::numeric_limits<int>::max(), second = best;
        size_t bestT = 0;
        for (size_t t : ts)
        {
            const int d = descriptorDistance(dq, train.ptr<uint8_t>(static_cast<int>(t)));
            if (d < best)
            {
                second = best;
                best = d;
                bestT = t;
            }
            else if (d < second)
            {
                second = d;
            }
        }
        if (best > max_distance || static_cast<float>(best) >= ratio * static_cast<float>(second))
            continue;
        if (best < bestForTrain[bestT].distance)
            bestForTrain[bestT] = {q, bestT, best};
    }
    std::vector<DescriptorMatch> out;
    for (const DescriptorMatch& m : bestForTrain)
        if (m.distance != std::numeric_limits<int>::max())
            out.push_back(m);
    return out;
}
}  // namespace smap::features
