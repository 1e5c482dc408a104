// The project's class labels: id, name, display colour and a prior of being a mover, loaded from
// config/labels/*.csv (PASCAL VOC by default). Label images hold these ids; 255 is "void".
#pragma once

#include <opencv2/core/mat.hpp>
#include <optional>
#include <string>
#include <vector>

namespace smap::core
{
struct Label
{
    int id = 0;
    std::string name;
    cv::Vec3b colourBgr;        ///< display colour (OpenCV channel order)
    double dynamicPrior = 0.0;  ///< how likely the class moves, in [0, 1] (person 0.9)
};

class LabelSet
{
public:
    /// Ids 0..n-1 in order. Label images use them; kVoid marks unknown / unlabelled pixels.
    static constexpr int kVoid = 255;

    LabelSet() = default;
    explicit LabelSet(std::vector<Label> labels);  ///< throws InputError unless ids are 0..n-1

    /// The 21 PASCAL VOC 2012 classes with the VOC colour map (same as config/labels/voc.csv).
    static LabelSet pascalVoc();
    /// CSV "id,name,r,g,b,dynamic_prior" with a header line; '#' starts a comment. Throws
    /// InputError naming the file and line.
    static LabelSet loadCsv(const std::string& path);
    std::string toCsv() const;

    size_t size() const { return labels_.size(); }
    bool empty() const { return labels_.empty(); }
    const Label& operator[](size_t id) const { return labels_.at(id); }
    const std::vector<Label>& labels() const { return labels_; }
    /// Id of a class by name (case-sensitive), or nullopt.
    std::optional<int> find(const std::string& name) const;
    /// Id by name; throws InputError listing the known names.
    int idOf(const std::string& name) const;

    /// Per class id: whether its dynamic prior is at least `minPrior` (the movable classes).
    std::vector<bool> movable(double minPrior) const;

    /// Display colour of a class id (BGR); black for void and ids outside the set.
    cv::Vec3b colourOf(int id) const;
    /// BGR picture of a CV_8UC1 label image (void and unknown ids black).
    cv::Mat colourise(const cv::Mat& labels) const;
    /// `bgr` blended with the label colours (background 0 and void left as they are).
    cv::Mat overlay(const cv::Mat& bgr, const cv::Mat& labels, double alpha = 0.6) const;

private:
    std::vector<Label> labels_;
};

/// CV_8UC1: 255 where the label image `labels` (CV_8UC1 class ids) holds a class marked in
/// `classes` (e.g. LabelSet::movable), 0 elsewhere (void and ids beyond `classes` included).
cv::Mat classMask(const cv::Mat& labels, const std::vector<bool>& classes);
}  // namespace smap::core
