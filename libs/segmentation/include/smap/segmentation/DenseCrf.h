// The fully connected CRF of Kraehenbuehl and Koltun (NIPS 2011) over a segmenter's output:
// mean-field inference with an appearance (bilateral) and a smoothness (Gaussian) kernel,
// message passing by permutohedral-lattice filtering (linear in the number of pixels).
#pragma once

#include <mrpt/config/CLoadableOptions.h>

#include <memory>
#include <opencv2/core/mat.hpp>
#include <string>

#include "smap/core/OptionFields.h"

namespace smap::segmentation
{
/// [crf] section. Defaults: the dense-CRF literature's (docs/method.md section 3), except
/// appearance_xy = 20 px (literature 80, for ~500 px wide images), tuned on 7-Scenes with
/// composited people at 320x240 (docs/segmentation.md).
struct DenseCrfParameters : public mrpt::config::CLoadableOptions
{
    bool enabled = true;
    int iterations = 5;  ///< mean-field iterations (CRF-RNN: 5 in training, 10 at test)
    /// Appearance kernel w1 exp(-|p_i - p_j|^2 / 2 theta_a^2 - |I_i - I_j|^2 / 2 theta_b^2):
    /// pixels (of the image the CRF runs on) and colour units (0-255 per channel).
    double appearance_weight = 10.0;
    double appearance_xy = 20.0;  ///< literature: 80
    double appearance_rgb = 13.0;
    /// Smoothness kernel w2 exp(-|p_i - p_j|^2 / 2 theta_g^2).
    double smoothness_weight = 3.0;
    double smoothness_xy = 3.0;
    /// Label compatibility mu: empty = Potts (mu = 1 between different labels, 0 for the same);
    /// else a CSV file of labels x labels numbers (row = label of i, column = label of j).
    std::string compatibility;
    /// Probabilities below this are raised to it before taking the unary -log p.
    double probability_floor = 1e-5;

    void loadFromConfigFile(const mrpt::config::CConfigFileBase& cfg,
                            const std::string& section) override;
    void saveToConfigFile(mrpt::config::CConfigFileBase& cfg,
                          const std::string& section) const override;
    /// Every key of the section (default [crf]), listed once for loading and saving.
    core::OptionFields fields(const std::string& section);
};

class DenseCrf
{
public:
    /// Throws core::InputError when the compatibility file is unreadable or not labels x labels.
    DenseCrf(const DenseCrfParameters& params, int labelCount);
    ~DenseCrf();
    DenseCrf(const DenseCrf&) = delete;
    DenseCrf& operator=(const DenseCrf&) = delete;

    /// Mean-field inference. `bgr`: CV_8UC3 h x w; `probabilities`: CV_32FC1, labels x (w*h)
    /// (SegmentationResult's layout). Returns the refined marginals in the same layout.
    ///
    /// Each kernel k is used symmetrically normalised, D^-1/2 K D^-1/2 with D = K 1 (as the
    /// reference implementation's default), which makes messages independent of the lattice's
    /// scale; the sums run over all pixels j, i included.
    ///
    /// The smoothness kernel depends on the image size only: it is built once per size and
    /// kept (so refine is not const; use one DenseCrf per thread).
    cv::Mat refine(const cv::Mat& bgr, const cv::Mat& probabilities);

    /// Kernel features, one row per pixel (row v * w + u): (u, v, b, g, r) / (theta_a, theta_b)
    /// and (u, v) / theta_g.
    cv::Mat appearanceFeatures(const cv::Mat& bgr) const;
    cv::Mat smoothnessFeatures(int width, int height) const;

    /// labels x labels, row = label of the pixel updated.
    const cv::Mat& compatibility() const { return compatibility_; }
    bool isPotts() const { return potts_; }
    const DenseCrfParameters& parameters() const { return params_; }

private:
    struct Kernel;
    DenseCrfParameters params_;
    std::unique_ptr<Kernel> appearance_;  ///< rebuilt for every image (buffers reused)
    std::unique_ptr<Kernel> smoothness_;  ///< for images of smoothness_->size
    cv::Mat scratch_[4];                  ///< refine's buffers, kept between calls
    int labelCount_;
    cv::Mat compatibility_;
    bool potts_ = true;
};
}  // namespace smap::segmentation
