// The dense CRF against a brute-force O(N^2) mean field with exact Gaussian kernels, and the
// permutohedral lattice against exact Gaussian filtering.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <opencv2/core.hpp>
#include <random>

#include "TestData.h"
#include "smap/segmentation/DenseCrf.h"
#include "smap/segmentation/PermutohedralLattice.h"
#include "smap/segmentation/SegmentationResult.h"

using namespace smap;
using segmentation::DenseCrf;
using segmentation::DenseCrfParameters;
using segmentation::PermutohedralLattice;

namespace
{
/// Exact K with k_ij = exp(-|f_i - f_j|^2 / 2), all j (i included).
cv::Mat exactKernel(const cv::Mat& f)
{
    cv::Mat k(f.rows, f.rows, CV_64FC1);
    for (int i = 0; i < f.rows; i++)
        for (int j = 0; j < f.rows; j++)
        {
            double d2 = 0.0;
            for (int c = 0; c < f.cols; c++)
            {
                const double d = f.at<float>(i, c) - f.at<float>(j, c);
                d2 += d * d;
            }
            k.at<double>(i, j) = std::exp(-0.5 * d2);
        }
    return k;
}

/// D^-1/2 K D^-1/2 of an exact kernel.
cv::Mat normalisedExact(const cv::Mat& f)
{
    cv::Mat k = exactKernel(f);
    cv::Mat deg;
    cv::reduce(k, deg, 1, cv::REDUCE_SUM);
    for (int i = 0; i < k.rows; i++)
        for (int j = 0; j < k.cols; j++)
            k.at<double>(i, j) /= std::sqrt(deg.at<double>(i) * deg.at<double>(j));
    return k;
}

/// Brute-force mean field of the same model as DenseCrf::refine (Potts or a matrix).
cv::Mat bruteForceMeanField(const DenseCrf& crf, const cv::Mat& bgr, const cv::Mat& probs)
{
    const auto& p = crf.parameters();
    const cv::Mat ka = normalisedExact(crf.appearanceFeatures(bgr));
    const cv::Mat ks = normalisedExact(crf.smoothnessFeatures(bgr.cols, bgr.rows));
    cv::Mat mu;
    crf.compatibility().convertTo(mu, CV_64FC1);
    cv::Mat unary;
    cv::transpose(probs, unary);  // pixels x labels
    unary.convertTo(unary, CV_64FC1);
    cv::max(unary, p.probability_floor, unary);
    cv::log(unary, unary);
    unary = -unary;
    auto softmax = [](const cv::Mat& e)
    {
        cv::Mat q(e.size(), CV_64FC1);
        for (int i = 0; i < e.rows; i++)
        {
            double lo = 1e300, sum = 0.0;
            for (int k = 0; k < e.cols; k++)
                lo = std::min(lo, e.at<double>(i, k));
            for (int k = 0; k < e.cols; k++)
                sum += q.at<double>(i, k) = std::exp(lo - e.at<double>(i, k));
            for (int k = 0; k < e.cols; k++)
                q.at<double>(i, k) /= sum;
        }
        return q;
    };
    cv::Mat q = softmax(unary);
    for (int it = 0; it < p.iterations; it++)
    {
        const cv::Mat m = p.appearance_weight * (ka * q) + p.smoothness_weight * (ks * q);
        q = softmax(unary + m * mu.t());
    }
    cv::Mat out;
    cv::transpose(q, out);
    out.convertTo(out, CV_32FC1);
    return out;
}

/// A small image of three colour regions (left, right, a square) and noisy CNN-like
/// probabilities: the true label with p ~ 0.6, a wrong one in 25% of the pixels.
struct Scene
{
    cv::Mat bgr, truth, probs;
};
Scene makeScene(int w, int h, int labels, unsigned seed)
{
    Scene s;
    s.bgr.create(h, w, CV_8UC3);
    s.truth.create(h, w, CV_8UC1);
    std::mt19937 rng(seed);
    std::normal_distribution<double> noise(0.0, 6.0);
    std::uniform_real_distribution<double> uni(0.0, 1.0);
    const cv::Vec3b colours[3] = {{40, 60, 200}, {200, 180, 30}, {90, 220, 90}};
    for (int v = 0; v < h; v++)
        for (int u = 0; u < w; u++)
        {
            int l = u < w / 2 ? 0 : 1;
            if (std::abs(u - w / 2) < w / 6 && std::abs(v - h / 2) < h / 4)
                l = 2;
            s.truth.at<uint8_t>(v, u) = static_cast<uint8_t>(l);
            for (int k = 0; k < 3; k++)
                s.bgr.at<cv::Vec3b>(v, u)[k] = cv::saturate_cast<uchar>(colours[l][k] + noise(rng));
        }
    s.probs.create(labels, w * h, CV_32FC1);
    for (int i = 0; i < w * h; i++)
    {
        int l = s.truth.at<uint8_t>(i / w, i % w);
        if (uni(rng) < 0.25)
            l = (l + 1 + static_cast<int>(uni(rng) * (labels - 1))) % labels;
        const float top = 0.45f + 0.3f * static_cast<float>(uni(rng));
        for (int k = 0; k < labels; k++)
            s.probs.at<float>(k, i) = k == l ? top : (1.0f - top) / static_cast<float>(labels - 1);
    }
    return s;
}

double agreement(const cv::Mat& a, const cv::Mat& b)
{
    return 1.0 - static_cast<double>(cv::countNonZero(a != b)) / static_cast<double>(a.total());
}
}  // namespace

TEST(PermutohedralLattice, NormalisedFilteringMatchesAUnitGaussian)
{
    // Offset 0: small lattice coordinates (packed keys); 900: large ones (the general path).
    for (const auto& [d, offset] : {std::pair{2, 0.0f}, std::pair{5, 0.0f}, std::pair{5, 900.0f}})
    {
        std::mt19937 rng(7 + d);
        std::uniform_real_distribution<float> pos(offset, offset + 4.0f);
        const int n = 1500;
        cv::Mat f(n, d, CV_32FC1), x(n, 2, CV_32FC1);
        for (int i = 0; i < n; i++)
        {
            for (int c = 0; c < d; c++)
                f.at<float>(i, c) = pos(rng);
            x.at<float>(i, 0) = f.at<float>(i, 0) > offset + 2.0f ? 1.0f : 0.0f;  // a step
            x.at<float>(i, 1) = 1.0f;
        }
        const PermutohedralLattice lattice(f);
        EXPECT_GT(lattice.vertexCount(), 0);
        cv::Mat ones(n, 1, CV_32FC1, cv::Scalar(1.0f)), degree, filtered;
        lattice.filter(ones, degree);
        lattice.filter(x, filtered);
        for (int i = 0; i < n; i++)
            ASSERT_NEAR(filtered.at<float>(i, 1), degree.at<float>(i), 1e-3 * degree.at<float>(i));
        // The normalised (weighted-average) response against exact Gaussians of standard
        // deviation s: the lattice's constant cancels, and s = 1 must fit best.
        auto meanError = [&](double s)
        {
            double sum = 0.0;
            for (int i = 0; i < n; i++)
            {
                double num = 0.0, den = 0.0;
                for (int j = 0; j < n; j++)
                {
                    double d2 = 0.0;
                    for (int c = 0; c < d; c++)
                    {
                        const double q = f.at<float>(i, c) - f.at<float>(j, c);
                        d2 += q * q;
                    }
                    const double k = std::exp(-0.5 * d2 / (s * s));
                    num += k * x.at<float>(j, 0);
                    den += k;
                }
                sum += std::abs(num / den - filtered.at<float>(i, 0) / filtered.at<float>(i, 1));
            }
            return sum / n;
        };
        const double atOne = meanError(1.0);
        EXPECT_LT(atOne, 0.025) << "d = " << d;
        EXPECT_LT(atOne, meanError(0.8)) << "d = " << d;
        EXPECT_LT(atOne, meanError(1.25)) << "d = " << d;
    }
}

TEST(DenseCrf, MatchesBruteForceMeanFieldOnASmallImage)
{
    const Scene s = makeScene(30, 22, 4, 3);
    DenseCrfParameters p;
    p.appearance_xy = 8.0;  // kernels scaled to the tiny image
    p.smoothness_xy = 1.5;
    for (const int iterations : {1, 5})
    {
        p.iterations = iterations;
        DenseCrf crf(p, 4);
        const cv::Mat fast = crf.refine(s.bgr, s.probs);
        const cv::Mat exact = bruteForceMeanField(crf, s.bgr, s.probs);
        const double maxDiff = cv::norm(fast, exact, cv::NORM_INF);
        const double meanDiff =
            cv::norm(fast, exact, cv::NORM_L1) / static_cast<double>(fast.total());
        EXPECT_LT(meanDiff, 0.02) << iterations << " iterations";
        EXPECT_LT(maxDiff, 0.25) << iterations << " iterations";
        const cv::Mat lf = segmentation::argmaxColumns(fast, 30, 22);
        const cv::Mat le = segmentation::argmaxColumns(exact, 30, 22);
        EXPECT_GT(agreement(lf, le), 0.97) << iterations << " iterations";
    }
}

TEST(DenseCrf, CleansNoisyLabelsAlongColourEdges)
{
    const Scene s = makeScene(96, 72, 5, 11);
    DenseCrfParameters p;
    p.appearance_xy = 20.0;
    DenseCrf crf(p, 5);
    const cv::Mat before = segmentation::argmaxColumns(s.probs, 96, 72);
    const cv::Mat after = segmentation::argmaxColumns(crf.refine(s.bgr, s.probs), 96, 72);
    const double a0 = agreement(before, s.truth), a1 = agreement(after, s.truth);
    EXPECT_LT(a0, 0.80);
    EXPECT_GT(a1, 0.98) << "noisy " << a0;
    // Marginals stay distributions.
    cv::Mat q = crf.refine(s.bgr, s.probs), sums;
    cv::reduce(q, sums, 0, cv::REDUCE_SUM);
    double lo = 0, hi = 0;
    cv::minMaxLoc(sums, &lo, &hi);
    EXPECT_NEAR(lo, 1.0, 1e-4);
    EXPECT_NEAR(hi, 1.0, 1e-4);
}

TEST(DenseCrf, CompatibilityMatrixFromFile)
{
    const Scene s = makeScene(30, 22, 3, 5);
    test::TempDir dir;
    {
        std::ofstream f(dir / "potts.csv");
        f << "# Potts, written out\n0,1,1\n1,0,1\n1,1,0\n";
        std::ofstream g(dir / "attract.csv");
        g << "0 1 1\n1 0 0.2\n1 0.2 0\n";
        std::ofstream b(dir / "bad.csv");
        b << "0 1\n1 0\n";
    }
    DenseCrfParameters p;
    p.appearance_xy = 8.0;
    DenseCrf potts(p, 3);
    EXPECT_TRUE(potts.isPotts());
    p.compatibility = dir / "potts.csv";
    DenseCrf fromFile(p, 3);
    EXPECT_TRUE(fromFile.isPotts());
    EXPECT_LT(cv::norm(potts.refine(s.bgr, s.probs), fromFile.refine(s.bgr, s.probs), cv::NORM_INF),
              1e-5);

    // A general matrix runs the general update and matches the brute force.
    p.compatibility = dir / "attract.csv";
    DenseCrf general(p, 3);
    EXPECT_FALSE(general.isPotts());
    const cv::Mat fast = general.refine(s.bgr, s.probs);
    const cv::Mat exact = bruteForceMeanField(general, s.bgr, s.probs);
    EXPECT_LT(cv::norm(fast, exact, cv::NORM_L1) / static_cast<double>(fast.total()), 0.02);

    p.compatibility = dir / "bad.csv";
    EXPECT_NE(test::inputErrorOf([&] { DenseCrf c(p, 3); }).find("bad.csv"), std::string::npos);
    p.compatibility = dir / "missing.csv";
    EXPECT_NE(test::inputErrorOf([&] { DenseCrf c(p, 3); }).find("missing.csv"), std::string::npos);
}

TEST(SegmentationResult, ResizeKeepsDistributionsAndLabels)
{
    cv::Mat probs(3, 4 * 2, CV_32FC1, cv::Scalar(0.1f));
    for (int i = 0; i < 8; i++)
        probs.at<float>(i % 4 < 2 ? 0 : 2, i) = 0.8f;
    const auto r = segmentation::SegmentationResult::fromProbabilities(probs, 4, 2);
    EXPECT_EQ(r.labels.at<uint8_t>(0, 0), 0);
    EXPECT_EQ(r.labels.at<uint8_t>(1, 3), 2);
    const auto big = r.resized(8, 4);
    EXPECT_EQ(big.width(), 8);
    EXPECT_EQ(big.height(), 4);
    EXPECT_EQ(big.labels.at<uint8_t>(0, 0), 0);
    EXPECT_EQ(big.labels.at<uint8_t>(3, 7), 2);
    cv::Mat sums;
    cv::reduce(big.probabilities, sums, 0, cv::REDUCE_SUM);
    EXPECT_LT(cv::norm(sums, cv::Mat::ones(1, 32, CV_32FC1), cv::NORM_INF), 1e-5);
}

TEST(PermutohedralLattice, SameFilteringWhateverTheThreadCount)
{
    // Points are hashed in stripes, one per thread, and the stripes' tables merged: the
    // lattice (vertex count) and the filtering must not depend on how many there are.
    std::mt19937 rng(3);
    std::uniform_real_distribution<float> pos(0.0f, 8.0f);
    cv::Mat f(3000, 5, CV_32FC1), x(3000, 3, CV_32FC1);
    for (int i = 0; i < f.rows; i++)
    {
        for (int c = 0; c < 5; c++)
            f.at<float>(i, c) = pos(rng);
        for (int c = 0; c < 3; c++)
            x.at<float>(i, c) = pos(rng);
    }
    const int before = cv::getNumThreads();
    cv::Mat reference;
    int vertices = 0;
    for (const int threads : {1, 3})
    {
        cv::setNumThreads(threads);
        const PermutohedralLattice lattice(f);
        cv::Mat out;
        lattice.filter(x, out);
        if (reference.empty())
        {
            reference = out;
            vertices = lattice.vertexCount();
            continue;
        }
        EXPECT_EQ(lattice.vertexCount(), vertices);
        EXPECT_LT(cv::norm(out, reference, cv::NORM_INF), 1e-4 * cv::norm(reference, cv::NORM_INF));
    }
    cv::setNumThreads(before);
}
