#include "smap/apps/KeyFrameScorer.h"

#include <filesystem>
#include <opencv2/imgcodecs.hpp>

#include "smap/core/InputError.h"

namespace fs = std::filesystem;

namespace smap::apps
{
namespace
{
std::vector<std::pair<int, std::string>> scoredClasses(const core::LabelSet& labels)
{
    std::vector<std::pair<int, std::string>> out;
    for (const auto& l : labels.labels())
        if (l.id != 0)
            out.emplace_back(l.id, l.name);
    return out;
}

cv::Mat readTruth(const fs::path& path, const cv::Size& size)
{
    if (!fs::exists(path))
        return {};
    cv::Mat m = cv::imread(path.string(), cv::IMREAD_UNCHANGED);
    if (m.empty() || m.type() != CV_8UC1 || m.size() != size)
        throw core::InputError("ground-truth image '" + path.string() +
                               "' is not an 8-bit single-channel image of the frame's size");
    return m;
}
}  // namespace

KeyFrameScorer::KeyFrameScorer(std::string gtDirectory, const core::LabelSet& labels,
                               bool scoreLabels, int voidLabel)
    : dir_(std::move(gtDirectory)),
      scoreLabels_(scoreLabels && fs::is_directory(fs::path(dir_) / "labels")),
      dynamic_({{1, "dynamic"}})
{
    if (scoreLabels_)
    {
        eval::SegmentationScoreOptions o;
        o.voidLabel = voidLabel;
        segmentation_.emplace(scoredClasses(labels), o);
    }
}

std::string KeyFrameScorer::findFor(const std::string& input)
{
    const fs::path p(input);
    const bool folder = fs::is_directory(p);
    const fs::path candidates[] = {folder ? p : fs::path(), folder ? p / "gt" : fs::path(),
                                   p.parent_path() / (p.stem().string() + "_gt")};
    for (const auto& c : candidates)
        if (!c.empty() && (fs::is_directory(c / "labels") || fs::is_directory(c / "dynamic")))
            return c.string();
    return {};
}

void KeyFrameScorer::add(const std::string& frameName, const maps::CObservationSemanticRGBD& obs)
{
    const cv::Size size = obs.labels.size();
    const std::string file = frameName + ".png";
    const cv::Mat truthLabels =
        scoreLabels_ ? readTruth(fs::path(dir_) / "labels" / file, size) : cv::Mat();
    const cv::Mat truthDynamic = readTruth(fs::path(dir_) / "dynamic" / file, size);
    std::lock_guard<std::mutex> lock(mutex_);
    if (truthLabels.empty() && truthDynamic.empty())
    {
        missing_++;
        return;
    }
    scored_++;
    if (!truthLabels.empty())
        segmentation_->addFrame(truthLabels, obs.labels);
    if (!truthDynamic.empty())
    {
        cv::Mat t = truthDynamic > 0;
        cv::Mat p = obs.dynamicMask > 0;
        // 0/255 masks -> 0/1 labels.
        dynamic_.addFrame(t / 255, p / 255);
    }
}

core::JsonValue KeyFrameScorer::toJson() const
{
    std::lock_guard<std::mutex> lock(mutex_);
    auto j = core::JsonValue::object();
    j.set("ground_truth", dir_);
    j.set("frames_scored", static_cast<uint64_t>(scored_));
    j.set("frames_without_truth", static_cast<uint64_t>(missing_));
    if (segmentation_ && segmentation_->frames() > 0)
        j.set("segmentation", segmentation_->toJson());
    if (dynamic_.frames() > 0)
        j.set("dynamic_mask", dynamic_.toJson());
    return j;
}

std::string KeyFrameScorer::toText() const
{
    std::lock_guard<std::mutex> lock(mutex_);
    std::string s;
    if (segmentation_ && segmentation_->frames() > 0)
        s += "keyframe segmentation (" + std::to_string(segmentation_->frames()) +
             " keyframes):\n" + segmentation_->toText();
    if (dynamic_.frames() > 0)
        s += "Algorithm 1 dynamic mask (" + std::to_string(dynamic_.frames()) + " keyframes):\n" +
             dynamic_.toText();
    return s;
}
}  // namespace smap::apps
