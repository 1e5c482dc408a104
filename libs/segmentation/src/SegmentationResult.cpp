#include "smap/segmentation/SegmentationResult.h"

#include <algorithm>
#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>
#include <vector>

namespace smap::segmentation
{
cv::Mat SegmentationResult::plane(int k) const
{
    return probabilities.row(k).reshape(1, height());
}

cv::Mat SegmentationResult::labelConfidence() const
{
    cv::Mat out(height(), width(), CV_32FC1);
    for (int v = 0; v < height(); v++)
    {
        const auto* l = labels.ptr<uint8_t>(v);
        auto* o = out.ptr<float>(v);
        for (int u = 0; u < width(); u++)
            o[u] = l[u] < labelCount() ? probabilities.at<float>(l[u], v * width() + u) : 0.0f;
    }
    return out;
}

SegmentationResult SegmentationResult::fromProbabilities(cv::Mat probabilities, int width,
                                                         int height)
{
    CV_Assert(probabilities.type() == CV_32FC1 && probabilities.cols == width * height &&
              probabilities.rows > 0 && probabilities.rows <= 255);
    SegmentationResult r;
    r.labels = argmaxColumns(probabilities, width, height);
    r.probabilities = std::move(probabilities);
    return r;
}

SegmentationResult SegmentationResult::resized(int newWidth, int newHeight) const
{
    if (newWidth == width() && newHeight == height())
        return *this;
    const int n = labelCount();
    cv::Mat out(n, newWidth * newHeight, CV_32FC1);
    // Bilinear weights sum to one: columns stay distributions (to float rounding).
    cv::parallel_for_(cv::Range(0, n),
                      [&](const cv::Range& range)
                      {
                          for (int k = range.start; k < range.end; k++)
                          {
                              cv::Mat dst = out.row(k).reshape(1, newHeight);
                              cv::resize(plane(k), dst, cv::Size(newWidth, newHeight), 0, 0,
                                         cv::INTER_LINEAR);
                          }
                      });
    return fromProbabilities(out, newWidth, newHeight);
}

namespace
{
/// Pixels are processed in blocks of this many columns: each class row of a block is
/// contiguous, and a block of all classes stays in cache.
constexpr int kBlock = 1024;
}  // namespace

void softmaxColumns(cv::Mat& scores)
{
    CV_Assert(scores.type() == CV_32FC1 && scores.isContinuous());
    const int n = scores.rows, pixels = scores.cols;
    cv::parallel_for_(cv::Range(0, (pixels + kBlock - 1) / kBlock),
                      [&](const cv::Range& range)
                      {
                          std::vector<float> best(kBlock), sum(kBlock);
                          for (int b = range.start; b < range.end; b++)
                          {
                              const int first = b * kBlock;
                              const int count = std::min(kBlock, pixels - first);
                              std::copy_n(scores.ptr<float>(0) + first, count, best.begin());
                              for (int k = 1; k < n; k++)
                              {
                                  const float* s = scores.ptr<float>(k) + first;
                                  for (int i = 0; i < count; i++)
                                      best[i] = std::max(best[i], s[i]);
                              }
                              std::fill_n(sum.begin(), count, 0.0f);
                              for (int k = 0; k < n; k++)
                              {
                                  float* s = scores.ptr<float>(k) + first;
                                  for (int i = 0; i < count; i++)
                                      s[i] -= best[i];
                                  cv::Mat row(1, count, CV_32FC1, s);
                                  cv::exp(row, row);
                                  for (int i = 0; i < count; i++)
                                      sum[i] += s[i];
                              }
                              for (int i = 0; i < count; i++)
                                  sum[i] = 1.0f / sum[i];
                              for (int k = 0; k < n; k++)
                              {
                                  float* s = scores.ptr<float>(k) + first;
                                  for (int i = 0; i < count; i++)
                                      s[i] *= sum[i];
                              }
                          }
                      });
}

cv::Mat argmaxColumns(const cv::Mat& probabilities, int width, int height)
{
    CV_Assert(probabilities.type() == CV_32FC1 && probabilities.cols == width * height);
    cv::Mat labels(height, width, CV_8UC1);
    const int n = probabilities.rows, pixels = probabilities.cols;
    cv::parallel_for_(cv::Range(0, (pixels + kBlock - 1) / kBlock),
                      [&](const cv::Range& range)
                      {
                          std::vector<float> best(kBlock);
                          for (int b = range.start; b < range.end; b++)
                          {
                              const int first = b * kBlock;
                              const int count = std::min(kBlock, pixels - first);
                              uint8_t* l = labels.ptr<uint8_t>() + first;
                              std::copy_n(probabilities.ptr<float>(0) + first, count, best.begin());
                              std::fill_n(l, count, uint8_t{0});
                              for (int k = 1; k < n; k++)
                              {
                                  const float* p = probabilities.ptr<float>(k) + first;
                                  for (int i = 0; i < count; i++)
                                  {
                                      const bool higher = p[i] > best[i];
                                      best[i] = higher ? p[i] : best[i];
                                      l[i] = higher ? static_cast<uint8_t>(k) : l[i];
                                  }
                              }
                          }
                      });
    return labels;
}
}  // namespace smap::segmentation
