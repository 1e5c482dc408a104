// Gaussian filtering in a d-dimensional feature space in time linear in the number of points:
// the permutohedral lattice of Adams, Baek and Davis (Eurographics 2010). Each point splats its
// value onto the d+1 vertices of the lattice simplex enclosing it, the lattice is blurred along
// its d+1 axes with a [1/2 1 1/2] kernel, and values are sliced back with the same barycentric
// weights. Result: out_i ~ c * sum_j exp(-|f_i - f_j|^2 / 2) in_j for an unknown constant c
// (cancelled by normalising, as DenseCrf does).
#pragma once

#include <opencv2/core/mat.hpp>
#include <vector>

namespace smap::segmentation
{
class PermutohedralLattice
{
public:
    static constexpr int kMaxDimensions = 16;

    /// `features`: CV_32FC1, one row per point, d columns (1 <= d <= kMaxDimensions), already
    /// divided by the kernel's standard deviation in each dimension. Builds the lattice (hashing).
    explicit PermutohedralLattice(const cv::Mat& features);
    /// Rebuilds the lattice for other points (reusing the buffers).
    void build(const cv::Mat& features);

    /// out = K in, where `in` and `out` are points x channels, CV_32FC1, row i = point i.
    /// `out` is reallocated as needed; uses OpenCV's parallel framework. With per-point
    /// factors (n_ values, or null): out_i = outWeight outScale_i sum_j K_ij inScale_j in_j.
    void filter(const cv::Mat& in, cv::Mat& out, const float* inScale = nullptr,
                const float* outScale = nullptr, float outWeight = 1.0f) const;

    /// The first half of filter: `in` splatted onto the lattice and blurred; vertexCount() x
    /// channels values for slicePoint. `scratch` (optional) keeps the work buffers between
    /// calls; `values` then shares one of them, valid until the next call with that scratch.
    void splatAndBlur(const cv::Mat& in, cv::Mat& values, const float* inScale = nullptr,
                      std::vector<cv::Mat>* scratch = nullptr) const;

    /// The second half for one point: dst[0..c) += scale * sum_r w_r values[vertex_r]. Inline
    /// so that callers fuse it with their own per-point work (and vectorise it with it); `dst`
    /// must not overlap `values`.
    void slicePoint(const cv::Mat& values, int point, float scale, float* dst) const
    {
        const int c = values.cols, d1 = d_ + 1;
        const size_t at = static_cast<size_t>(point) * d1;
        for (int r = 0; r < d1; r++)
        {
            const float w = weightOfPoint_[at + r] * scale;
            const float* src = values.ptr<float>(vertexOfPoint_[at + r]);
            int k = 0;
            for (; k + 8 <= c; k += 8)  // fixed-width blocks: these vectorise
                for (int j = 0; j < 8; j++)
                    dst[k + j] += w * src[k + j];
            for (; k < c; k++)
                dst[k] += w * src[k];
        }
    }

    int dimensions() const { return d_; }
    int pointCount() const { return n_; }
    int vertexCount() const { return vertexCount_; }

private:
    int d_ = 0;
    int n_ = 0;
    int vertexCount_ = 0;
    /// Point i's simplex: vertex ids and barycentric weights at [i * (d+1) + r].
    std::vector<int> vertexOfPoint_;
    std::vector<float> weightOfPoint_;
    /// Each point's remainder-0 simplex corner and coordinate ranks (build's scratch).
    std::vector<int> rem0_, rank_;
    /// Neighbours of vertex v along axis j: [(v * (d+1) + j) * 2 + {0, 1}], -1 where absent.
    std::vector<int> neighbours_;
};
}  // namespace smap::segmentation
