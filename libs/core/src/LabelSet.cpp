#include "smap/core/LabelSet.h"

#include <mrpt/core/format.h>

#include <algorithm>
#include <fstream>
#include <opencv2/core.hpp>
#include <sstream>

#include "smap/core/InputError.h"

namespace smap::core
{
namespace
{
/// The PASCAL VOC colour map (bit-interleaved id), BGR.
cv::Vec3b vocColour(int id)
{
    int r = 0, g = 0, b = 0, c = id;
    for (int j = 0; j < 8; j++)
    {
        r |= ((c >> 0) & 1) << (7 - j);
        g |= ((c >> 1) & 1) << (7 - j);
        b |= ((c >> 2) & 1) << (7 - j);
        c >>= 3;
    }
    return {static_cast<uchar>(b), static_cast<uchar>(g), static_cast<uchar>(r)};
}
}  // namespace

LabelSet::LabelSet(std::vector<Label> labels) : labels_(std::move(labels))
{
    if (labels_.size() > static_cast<size_t>(kVoid))
        throw InputError(
            mrpt::format("a label set has at most %d classes, not %zu", kVoid, labels_.size()));
    for (size_t i = 0; i < labels_.size(); i++)
    {
        if (labels_[i].id != static_cast<int>(i))
            throw InputError(
                mrpt::format("label '%s' has id %d where %zu was expected (ids "
                             "must be 0, 1, 2, ... in order)",
                             labels_[i].name.c_str(), labels_[i].id, i));
        for (size_t j = 0; j < i; j++)
            if (labels_[j].name == labels_[i].name)
                throw InputError("label name '" + labels_[i].name + "' appears twice");
    }
}

cv::Vec3b LabelSet::colourOf(int id) const
{
    return id >= 0 && static_cast<size_t>(id) < labels_.size()
               ? labels_[static_cast<size_t>(id)].colourBgr
               : cv::Vec3b(0, 0, 0);
}

LabelSet LabelSet::pascalVoc()
{
    static const char* const kNames[] = {
        "background", "aeroplane", "bicycle",     "bird",  "boat",        "bottle", "bus",
        "car",        "cat",       "chair",       "cow",   "diningtable", "dog",    "horse",
        "motorbike",  "person",    "pottedplant", "sheep", "sofa",        "train",  "tvmonitor"};
    std::vector<Label> v;
    for (int i = 0; i < 21; i++)
    {
        Label l;
        l.id = i;
        l.name = kNames[i];
        l.colourBgr = vocColour(i);
        // Animals and vehicles can move; a person almost always does in our scenes.
        const std::string n = l.name;
        if (n == "person")
            l.dynamicPrior = 0.9;
        else if (n == "bird" || n == "cat" || n == "cow" || n == "dog" || n == "horse" ||
                 n == "sheep")
            l.dynamicPrior = 0.7;
        else if (n == "aeroplane" || n == "bicycle" || n == "boat" || n == "bus" || n == "car" ||
                 n == "motorbike" || n == "train")
            l.dynamicPrior = 0.5;
        else if (n == "chair")
            l.dynamicPrior = 0.2;
        v.push_back(l);
    }
    return LabelSet(std::move(v));
}

LabelSet LabelSet::loadCsv(const std::string& path)
{
    std::ifstream f(path);
    if (!f)
        throw InputError("cannot open label table '" + path + "'");
    std::vector<Label> v;
    std::string line;
    int lineNo = 0;
    bool header = true;
    while (std::getline(f, line))
    {
        lineNo++;
        if (const auto hash = line.find('#'); hash != std::string::npos)
            line.erase(hash);
        if (line.find_first_not_of(" \t\r") == std::string::npos)
            continue;
        if (header)
        {
            header = false;
            if (line.rfind("id,", 0) == 0)
                continue;
            throw InputError(
                mrpt::format("%s:%d: expected the header "
                             "'id,name,r,g,b,dynamic_prior'",
                             path.c_str(), lineNo));
        }
        std::stringstream ss(line);
        std::vector<std::string> cells;
        std::string c;
        while (std::getline(ss, c, ','))
            cells.push_back(c);
        if (cells.size() != 6)
            throw InputError(mrpt::format("%s:%d: expected 6 comma-separated fields, got %zu",
                                          path.c_str(), lineNo, cells.size()));
        try
        {
            Label l;
            size_t used = 0;
            l.id = std::stoi(cells[0], &used);
            l.name = cells[1];
            l.name.erase(0, l.name.find_first_not_of(" \t"));
            l.name.erase(l.name.find_last_not_of(" \t\r") + 1);
            int rgb[3];
            for (int k = 0; k < 3; k++)
            {
                rgb[k] = std::stoi(cells[2 + k]);
                if (rgb[k] < 0 || rgb[k] > 255)
                    throw std::out_of_range("colour");
            }
            l.colourBgr = {static_cast<uchar>(rgb[2]), static_cast<uchar>(rgb[1]),
                           static_cast<uchar>(rgb[0])};
            l.dynamicPrior = std::stod(cells[5]);
            if (!(l.dynamicPrior >= 0.0 && l.dynamicPrior <= 1.0) || l.name.empty())
                throw std::out_of_range("prior");
            v.push_back(l);
        }
        catch (const std::logic_error&)
        {
            throw InputError(
                mrpt::format("%s:%d: bad label line '%s' (id, name, r, g, b in "
                             "0-255, dynamic_prior in [0, 1])",
                             path.c_str(), lineNo, line.c_str()));
        }
    }
    if (v.empty())
        throw InputError("label table '" + path + "' has no labels");
    try
    {
        return LabelSet(std::move(v));
    }
    catch (const InputError& e)
    {
        throw InputError(path + ": " + e.what());
    }
}

std::string LabelSet::toCsv() const
{
    std::string s = "id,name,r,g,b,dynamic_prior\n";
    for (const auto& l : labels_)
        s += mrpt::format("%d,%s,%d,%d,%d,%g\n", l.id, l.name.c_str(), l.colourBgr[2],
                          l.colourBgr[1], l.colourBgr[0], l.dynamicPrior);
    return s;
}

std::optional<int> LabelSet::find(const std::string& name) const
{
    for (const auto& l : labels_)
        if (l.name == name)
            return l.id;
    return std::nullopt;
}

int LabelSet::idOf(const std::string& name) const
{
    if (const auto id = find(name))
        return *id;
    std::string known;
    for (const auto& l : labels_)
        known += (known.empty() ? "" : ", ") + l.name;
    throw InputError("unknown class '" + name + "' (known: " + known + ")");
}

cv::Mat LabelSet::colourise(const cv::Mat& labels) const
{
    CV_Assert(labels.type() == CV_8UC1);
    cv::Mat out(labels.size(), CV_8UC3, cv::Scalar::all(0));
    for (int v = 0; v < labels.rows; v++)
    {
        const auto* l = labels.ptr<uint8_t>(v);
        auto* o = out.ptr<cv::Vec3b>(v);
        for (int u = 0; u < labels.cols; u++)
            if (l[u] < labels_.size())
                o[u] = labels_[l[u]].colourBgr;
    }
    return out;
}

cv::Mat LabelSet::overlay(const cv::Mat& bgr, const cv::Mat& labels, double alpha) const
{
    CV_Assert(bgr.type() == CV_8UC3 && labels.type() == CV_8UC1 && bgr.size() == labels.size());
    cv::Mat out = bgr.clone();
    for (int v = 0; v < labels.rows; v++)
    {
        const auto* l = labels.ptr<uint8_t>(v);
        auto* o = out.ptr<cv::Vec3b>(v);
        for (int u = 0; u < labels.cols; u++)
        {
            if (l[u] == 0 || l[u] >= labels_.size())
                continue;
            const cv::Vec3b c = labels_[l[u]].colourBgr;
            for (int k = 0; k < 3; k++)
                o[u][k] = cv::saturate_cast<uchar>((1.0 - alpha) * o[u][k] + alpha * c[k]);
        }
    }
    return out;
}
std::vector<bool> LabelSet::movable(double minPrior) const
{
    std::vector<bool> out(labels_.size(), false);
    for (const auto& l : labels_)
        out[static_cast<size_t>(l.id)] = l.dynamicPrior >= minPrior;
    return out;
}

cv::Mat classMask(const cv::Mat& labels, const std::vector<bool>& classes)
{
    cv::Mat table(1, 256, CV_8UC1, cv::Scalar(0));
    for (size_t id = 0; id < std::min<size_t>(classes.size(), 256); ++id)
        table.at<uint8_t>(0, static_cast<int>(id)) = classes[id] ? 255 : 0;
    cv::Mat mask;
    cv::LUT(labels, table, mask);
    return mask;
}
}  // namespace smap::core
