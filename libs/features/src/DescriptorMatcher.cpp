#include "smap/features/DescriptorMatcher.h"

#include <limits>
#include <numeric>

#include "smap/features/FeatureGrid.h"

namespace smap::features
{
namespace
{
constexpr int kNone = std::numeric_limits<int>::max();

// The core of both matchers: for each query row, the nearest of the rows
// `forEachCandidate(q, visit)` visits, with Lowe's ratio test; each train row keeps only its
// closest query.
template <typename ForEachCandidate>
std::vector<DescriptorMatch> matchOneToOne(const cv::Mat& query, const cv::Mat& train,
                                           const std::vector<size_t>& query_rows, float ratio,
                                           int max_distance, ForEachCandidate&& forEachCandidate)
{
    std::vector<DescriptorMatch> bestForTrain(static_cast<size_t>(train.rows), {0, 0, kNone});
    for (size_t q : query_rows)
    {
        const uint8_t* dq = query.ptr<uint8_t>(static_cast<int>(q));
        int best = kNone, second = kNone;
        size_t bestT = 0;
        forEachCandidate(q,
                         [&](size_t t)
                         {
                             const int d =
                                 descriptorDistance(dq, train.ptr<uint8_t>(static_cast<int>(t)));
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
                         });
        if (best > max_distance || static_cast<float>(best) >= ratio * static_cast<float>(second))
            continue;
        if (best < bestForTrain[bestT].distance)
            bestForTrain[bestT] = {q, bestT, best};
    }
    std::vector<DescriptorMatch> out;
    for (const DescriptorMatch& m : bestForTrain)
        if (m.distance != kNone)
            out.push_back(m);
    return out;
}

std::vector<size_t> allRows(int n)
{
    std::vector<size_t> rows(static_cast<size_t>(n));
    std::iota(rows.begin(), rows.end(), size_t{0});
    return rows;
}
}  // namespace

std::vector<DescriptorMatch> matchWithRatioTest(const cv::Mat& query, const cv::Mat& train,
                                                float ratio, int max_distance,
                                                const std::vector<size_t>& query_rows,
                                                const std::vector<size_t>& train_rows)
{
    const std::vector<size_t> qs = query_rows.empty() ? allRows(query.rows) : query_rows;
    const std::vector<size_t> ts = train_rows.empty() ? allRows(train.rows) : train_rows;
    return matchOneToOne(query, train, qs, ratio, max_distance,
                         [&ts](size_t, auto&& visit)
                         {
                             for (size_t t : ts)
                                 visit(t);
                         });
}

std::vector<DescriptorMatch> matchWithinRadius(const cv::Mat& query,
                                               const std::vector<cv::KeyPoint>& query_keypoints,
                                               const std::vector<cv::Point2f>& query_points,
                                               const cv::Mat& train, const FeatureGrid& train_grid,
                                               float radius, float ratio, int max_distance,
                                               const std::vector<size_t>& query_rows)
{
    return matchOneToOne(query, train, query_rows.empty() ? allRows(query.rows) : query_rows, ratio,
                         max_distance,
                         [&](size_t q, auto&& visit)
                         {
                             const int level = query_keypoints[q].octave;
                             train_grid.forEachNear(query_points[q].x, query_points[q].y, radius,
                                                    level - 1, level + 1, visit);
                         });
}
}  // namespace smap::features
