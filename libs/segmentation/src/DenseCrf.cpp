#include "smap/segmentation/DenseCrf.h"

#include <mrpt/config/CConfigFileBase.h>
#include <mrpt/core/format.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <opencv2/core.hpp>
#include <sstream>

#include "smap/core/InputError.h"
#include "smap/core/OptionFields.h"
#include "smap/segmentation/PermutohedralLattice.h"

namespace smap::segmentation
{
core::OptionFields DenseCrfParameters::fields(const std::string& section)
{
    core::OptionFields f(section, "crf");
    f.add("enabled", enabled)
        .add("iterations", iterations)
        .add("appearance_weight", appearance_weight)
        .add("appearance_xy", appearance_xy)
        .add("appearance_rgb", appearance_rgb)
        .add("smoothness_weight", smoothness_weight)
        .add("smoothness_xy", smoothness_xy)
        .add("compatibility", compatibility)
        .add("probability_floor", probability_floor);
    return f;
}

void DenseCrfParameters::loadFromConfigFile(const mrpt::config::CConfigFileBase& cfg,
                                            const std::string& section)
{
    fields(section).load(cfg);
    if (iterations < 0 || iterations > 100)
        throw core::InputError(
            mrpt::format("[crf] iterations = %d must be in [0, 100]", iterations));
    if (!(appearance_weight >= 0.0) || !(smoothness_weight >= 0.0))
        throw core::InputError(
            mrpt::format("[crf] appearance_weight = %g and smoothness_weight = %g must be >= 0",
                         appearance_weight, smoothness_weight));
    if (!(appearance_xy > 0.0) || !(appearance_rgb > 0.0) || !(smoothness_xy > 0.0))
        throw core::InputError(mrpt::format(
            "[crf] appearance_xy = %g, appearance_rgb = %g and smoothness_xy = %g must be > 0",
            appearance_xy, appearance_rgb, smoothness_xy));
    if (!(probability_floor > 0.0 && probability_floor < 0.5))
        throw core::InputError(
            mrpt::format("[crf] probability_floor = %g must be in (0, 0.5)", probability_floor));
}

void DenseCrfParameters::saveToConfigFile(mrpt::config::CConfigFileBase& cfg,
                                          const std::string& section) const
{
    // Saving only reads the fields the list points at.
    const_cast<DenseCrfParameters*>(this)->fields(section).save(cfg);
}

DenseCrf::DenseCrf(const DenseCrfParameters& params, int labelCount)
    : params_(params), labelCount_(labelCount)
{
    CV_Assert(labelCount > 0 && labelCount <= 255);
    compatibility_ = cv::Mat::ones(labelCount, labelCount, CV_32FC1) -
                     cv::Mat::eye(labelCount, labelCount, CV_32FC1);
    const std::string& path = params_.compatibility;
    if (path.empty() || path == "potts")
        return;
    std::ifstream f(path);
    if (!f)
        throw core::InputError("cannot open [crf] compatibility file '" + path + "'");
    std::vector<float> values;
    std::string line;
    int rows = 0;
    while (std::getline(f, line))
    {
        if (const auto hash = line.find('#'); hash != std::string::npos)
            line.erase(hash);
        for (char& ch : line)
            if (ch == ',')
                ch = ' ';
        std::stringstream ss(line);
        double v = 0.0;
        int cols = 0;
        while (ss >> v)
        {
            values.push_back(static_cast<float>(v));
            cols++;
        }
        if (!ss.eof())
            throw core::InputError(
                mrpt::format("%s:%d: not a number in '%s'", path.c_str(), rows + 1, line.c_str()));
        if (cols == 0)
            continue;
        if (cols != labelCount)
            throw core::InputError(
                mrpt::format("%s: row %d has %d values, expected %d (one "
                             "per label)",
                             path.c_str(), rows + 1, cols, labelCount));
        rows++;
    }
    if (rows != labelCount)
        throw core::InputError(mrpt::format("%s: %d rows, expected a %d x %d matrix", path.c_str(),
                                            rows, labelCount, labelCount));
    compatibility_ = cv::Mat(labelCount, labelCount, CV_32FC1, values.data()).clone();
    potts_ = cv::norm(compatibility_,
                      cv::Mat::ones(labelCount, labelCount, CV_32FC1) -
                          cv::Mat::eye(labelCount, labelCount, CV_32FC1),
                      cv::NORM_INF) == 0.0;
}

cv::Mat DenseCrf::appearanceFeatures(const cv::Mat& bgr) const
{
    CV_Assert(bgr.type() == CV_8UC3);
    cv::Mat f(bgr.rows * bgr.cols, 5, CV_32FC1);
    const float sxy = static_cast<float>(1.0 / params_.appearance_xy);
    const float srgb = static_cast<float>(1.0 / params_.appearance_rgb);
    for (int v = 0; v < bgr.rows; v++)
    {
        const auto* row = bgr.ptr<cv::Vec3b>(v);
        for (int u = 0; u < bgr.cols; u++)
        {
            float* p = f.ptr<float>(v * bgr.cols + u);
            p[0] = static_cast<float>(u) * sxy;
            p[1] = static_cast<float>(v) * sxy;
            for (int k = 0; k < 3; k++)
                p[2 + k] = static_cast<float>(row[u][k]) * srgb;
        }
    }
    return f;
}

cv::Mat DenseCrf::smoothnessFeatures(int width, int height) const
{
    cv::Mat f(width * height, 2, CV_32FC1);
    const float s = static_cast<float>(1.0 / params_.smoothness_xy);
    for (int v = 0; v < height; v++)
    {
        for (int u = 0; u < width; u++)
        {
            float* p = f.ptr<float>(v * width + u);
            p[0] = static_cast<float>(u) * s;
            p[1] = static_cast<float>(v) * s;
        }
    }
    return f;
}

/// A kernel ready for message passing: its lattice and the normalisation D^-1/2.
struct DenseCrf::Kernel
{
    explicit Kernel(const cv::Mat& features, cv::Size imageSize = {})
        : lattice(features), size(imageSize)
    {
        normalise();
    }

    void rebuild(const cv::Mat& features, cv::Size imageSize)
    {
        lattice.build(features);
        size = imageSize;
        normalise();
    }

    void normalise()
    {
        cv::Mat ones(lattice.pointCount(), 1, CV_32FC1, cv::Scalar(1.0f)), degree;
        lattice.filter(ones, degree);
        cv::max(degree, 1e-20f, degree);
        cv::sqrt(degree, norm);
        cv::divide(1.0, norm, norm);
    }

    PermutohedralLattice lattice;
    cv::Mat norm;
    cv::Size size;
    std::vector<cv::Mat> scratch;  ///< splatAndBlur's buffers, kept between calls
};

DenseCrf::~DenseCrf() = default;

namespace
{

/// Labels padded to a multiple of 8 in the pixel-major matrices (the lattice's vector width).
int paddedLabels(int labels)
{
    return (labels + 7) / 8 * 8;
}

/// Unary energies -log max(p, floor), pixels x padded labels (pads 0), from labels x pixels
/// probabilities.
void unaryEnergies(const cv::Mat& probabilities, float floor, cv::Mat& unary)
{
    const int labels = probabilities.rows, pixels = probabilities.cols;
    unary.create(pixels, paddedLabels(labels), CV_32FC1);
    cv::parallel_for_(cv::Range(0, pixels),
                      [&](const cv::Range& range)
                      {
                          cv::Mat rows = unary.rowRange(range.start, range.end);
                          rows.setTo(1.0f);
                          for (int k = 0; k < labels; k++)
                          {
                              const float* src = probabilities.ptr<float>(k);
                              for (int i = range.start; i < range.end; i++)
                                  unary.at<float>(i, k) = std::max(src[i], floor);
                          }
                          cv::log(rows, rows);
                          rows *= -1.0;
                      });
}

/// One mean-field step for pixels [begin, end), fused so each pixel's data stays in cache:
/// messages sliced from both kernels' blurred lattices, energy, softmax, written to q. With
/// Potts (mu = null), E_i(l) = U_i(l) - m_i(l) (see refine); else E = U + mu m. Pixels go in
/// blocks so that one vectorised cv::exp call covers many of them.
__attribute__((target_clones("avx2", "default"))) void meanFieldStep(
    const PermutohedralLattice& a, const cv::Mat& valuesA, const cv::Mat& normA, float weightA,
    const PermutohedralLattice& s, const cv::Mat& valuesS, const cv::Mat& normS, float weightS,
    const cv::Mat& unary, const cv::Mat* mu, int labels, cv::Mat& q, int begin, int end)
{
    const int padded = q.cols;
    constexpr int kBlock = 64;
    std::vector<float> energies(static_cast<size_t>(kBlock) * padded);
    float msg[256];
    for (int first = begin; first < end; first += kBlock)
    {
        const int count = std::min(kBlock, end - first);
        for (int b = 0; b < count; b++)
        {
            const int i = first + b;
            for (int k = 0; k < padded; k++)
                msg[k] = 0.0f;
            a.slicePoint(valuesA, i, weightA * normA.at<float>(i), msg);
            s.slicePoint(valuesS, i, weightS * normS.at<float>(i), msg);
            const float* u = unary.ptr<float>(i);
            float* e = energies.data() + static_cast<size_t>(b) * padded;
            if (!mu)
            {
                for (int k = 0; k < padded; k++)  // pads: msg 0, u 0; their exp is unused
                    e[k] = msg[k] - u[k];
            }
            else
            {
                for (int k = 0; k < labels; k++)
                {
                    const float* row = mu->ptr<float>(k);
                    float sum = 0.0f;
                    for (int l = 0; l < labels; l++)
                        sum += row[l] * msg[l];
                    e[k] = -u[k] - sum;
                }
                for (int k = labels; k < padded; k++)
                    e[k] = 0.0f;
            }
        }
        // Energies are bounded (unaries by -log(floor), messages by their weights): exp needs
        // no shift by the maximum.
        cv::Mat block(1, count * padded, CV_32FC1, energies.data());
        cv::exp(block, block);
        for (int b = 0; b < count; b++)
        {
            const float* e = energies.data() + static_cast<size_t>(b) * padded;
            float total = 0.0f;
            for (int k = 0; k < labels; k++)
                total += e[k];
            const float inv = 1.0f / total;
            float* dst = q.ptr<float>(first + b);
            for (int k = 0; k < padded; k++)
                dst[k] = k < labels ? e[k] * inv : 0.0f;
        }
    }
}

/// q from the unaries alone (the initialisation): q_i(l) = exp(-U_i(l)) / sum.
void unaryDistribution(const cv::Mat& unary, int labels, cv::Mat& q, int begin, int end)
{
    cv::Mat rows = q.rowRange(begin, end);
    cv::multiply(unary.rowRange(begin, end), -1.0, rows);
    cv::exp(rows, rows);
    for (int i = begin; i < end; i++)
    {
        float* dst = q.ptr<float>(i);
        float total = 0.0f;
        for (int k = 0; k < labels; k++)
            total += dst[k];
        for (int k = 0; k < q.cols; k++)
            dst[k] = k < labels ? dst[k] / total : 0.0f;
    }
}
}  // namespace

cv::Mat DenseCrf::refine(const cv::Mat& bgr, const cv::Mat& probabilities)
{
    CV_Assert(bgr.type() == CV_8UC3 && probabilities.type() == CV_32FC1 &&
              probabilities.rows == labelCount_ && probabilities.cols == bgr.rows * bgr.cols);
    if (params_.iterations == 0)
        return probabilities.clone();

    // Pixel-major from here on: a pixel's labels are contiguous for the lattice.
    const int labels = labelCount_;
    // Buffers are members, reused from call to call (no fresh pages to fault in).
    cv::Mat& unary = scratch_[0];
    unaryEnergies(probabilities, static_cast<float>(params_.probability_floor), unary);
    if (!appearance_)
        appearance_ = std::make_unique<Kernel>(appearanceFeatures(bgr), bgr.size());
    else
        appearance_->rebuild(appearanceFeatures(bgr), bgr.size());
    Kernel& appearance = *appearance_;
    if (!smoothness_ || smoothness_->size != bgr.size())
        smoothness_ = std::make_unique<Kernel>(smoothnessFeatures(bgr.cols, bgr.rows), bgr.size());
    Kernel& smoothness = *smoothness_;

    const int stripes = std::max(1, std::min(cv::getNumThreads(), 8));
    const cv::Range all(0, unary.rows);
    cv::Mat &q = scratch_[1], &valuesA = scratch_[2], &valuesS = scratch_[3];
    q.create(unary.size(), CV_32FC1);
    cv::parallel_for_(
        all, [&](const cv::Range& r) { unaryDistribution(unary, labels, q, r.start, r.end); },
        stripes);
    // mu = 1 - identity (Potts): E_i(l) = U_i(l) + sum_l' m_i(l') - m_i(l), where the sum is
    // the same for every l and cancels in the normalisation.
    const cv::Mat* mu = potts_ ? nullptr : &compatibility_;
    for (int it = 0; it < params_.iterations; it++)
    {
        appearance.lattice.splatAndBlur(q, valuesA, appearance.norm.ptr<float>(),
                                        &appearance.scratch);
        smoothness.lattice.splatAndBlur(q, valuesS, smoothness.norm.ptr<float>(),
                                        &smoothness.scratch);
        cv::parallel_for_(
            all,
            [&](const cv::Range& r)
            {
                meanFieldStep(appearance.lattice, valuesA, appearance.norm,
                              static_cast<float>(params_.appearance_weight), smoothness.lattice,
                              valuesS, smoothness.norm,
                              static_cast<float>(params_.smoothness_weight), unary, mu, labels, q,
                              r.start, r.end);
            },
            stripes);
    }
    // Back to labels x pixels.
    cv::Mat out(labels, unary.rows, CV_32FC1);
    cv::parallel_for_(
        all,
        [&](const cv::Range& r)
        {
            for (int k = 0; k < labels; k++)
            {
                float* dst = out.ptr<float>(k);
                for (int i = r.start; i < r.end; i++)
                    dst[i] = q.at<float>(i, k);
            }
        },
        stripes);
    return out;
}
}  // namespace smap::segmentation
