// Synthetic RGB-D inputs with known content for the io tests: TUM folders and rawlogs.
#pragma once

#include <mrpt/io/CFileGZOutputStream.h>
#include <mrpt/obs/CObservation3DRangeScan.h>
#include <mrpt/serialization/CArchive.h>

#include <filesystem>
#include <fstream>
#include <opencv2/imgcodecs.hpp>
#include <string>
#include <vector>

#include "smap/core/PinholeCamera.h"

namespace smap::test
{
inline core::PinholeCamera smallCamera(int w = 64, int h = 48, double f = 60.0)
{
    core::PinholeCamera c;
    c.width = w;
    c.height = h;
    c.fx = f;
    c.fy = f;
    c.cx = (w - 1) / 2.0;
    c.cy = (h - 1) / 2.0;
    return c;
}

/// Colour pattern that differs per frame and pixel.
inline cv::Mat patternColour(int w, int h, int seed)
{
    cv::Mat img(h, w, CV_8UC3);
    for (int v = 0; v < h; v++)
        for (int u = 0; u < w; u++)
            img.at<cv::Vec3b>(v, u) =
                cv::Vec3b(static_cast<uchar>(u * 3 + seed), static_cast<uchar>(v * 5 + 7 * seed),
                          static_cast<uchar>((u ^ v) + seed));
    return img;
}

/// Raw 16-bit depth: a ramp with some invalid (0) pixels.
inline cv::Mat patternDepthRaw(int w, int h, int seed)
{
    cv::Mat d(h, w, CV_16UC1);
    for (int v = 0; v < h; v++)
        for (int u = 0; u < w; u++)
            d.at<uint16_t>(v, u) = ((u + v + seed) % 17 == 0)
                                       ? 0
                                       : static_cast<uint16_t>(5000 + 37 * u + 11 * v + 101 * seed);
    return d;
}

/// Writes a TUM folder with `n` frames (PNG colour and depth); depth timestamps lag by `lag`.
inline void writeTumFolder(const std::string& dir, int n, double lag, bool withAssociations,
                           int w = 64, int h = 48)
{
    namespace fs = std::filesystem;
    fs::create_directories(fs::path(dir) / "rgb");
    fs::create_directories(fs::path(dir) / "depth");
    std::ofstream rgb(fs::path(dir) / "rgb.txt"), depth(fs::path(dir) / "depth.txt"),
        gt(fs::path(dir) / "groundtruth.txt");
    std::ofstream assoc;
    if (withAssociations)
        assoc.open(fs::path(dir) / "associations.txt");
    rgb << "# color images\n# timestamp filename\n";
    depth << "# depth maps\n";
    gt << "# timestamp tx ty tz qx qy qz qw\n";
    for (int i = 0; i < n; i++)
    {
        const double t = 100.0 + i / 30.0;
        const std::string name = "f" + std::to_string(i);
        cv::imwrite(dir + "/rgb/" + name + ".png", patternColour(w, h, i));
        cv::imwrite(dir + "/depth/" + name + ".png", patternDepthRaw(w, h, i));
        rgb << std::fixed << t << " rgb/" << name << ".png\n";
        depth << std::fixed << t + lag << " depth/" << name << ".png\n";
        gt << std::fixed << t << " " << 0.1 * i << " 0 0 0 0 0 1\n";
        if (withAssociations)
            assoc << std::fixed << t << " rgb/" << name << ".png " << t + lag << " depth/" << name
                  << ".png\n";
    }
}

/// Writes serializable entries to a rawlog; gzip-compressed when `gz`.
inline void writeRawlog(const std::string& path,
                        const std::vector<mrpt::serialization::CSerializable::Ptr>& entries,
                        bool gz = false)
{
    mrpt::io::CFileGZOutputStream f;
    f.open(path, gz ? 6 : 0);
    auto arch = mrpt::serialization::archiveFrom(f);
    for (const auto& e : entries)
        arch.WriteObject(e.get());
}

/// An observation whose depth and colour cameras coincide (the tum2rawlog convention).
inline mrpt::obs::CObservation3DRangeScan::Ptr makeCoincidentObservation(
    const core::PinholeCamera& cam, const cv::Mat& colour, const cv::Mat& raw, float units,
    double t)
{
    auto o = mrpt::obs::CObservation3DRangeScan::Create();
    o->timestamp = mrpt::Clock::fromDouble(t);
    o->sensorLabel = "KINECT";
    o->hasRangeImage = true;
    o->rangeUnits = units;
    o->rangeImage_setSize(raw.rows, raw.cols);
    for (int r = 0; r < raw.rows; r++)
        for (int c = 0; c < raw.cols; c++)
            o->rangeImage(r, c) = raw.at<uint16_t>(r, c);
    o->hasIntensityImage = true;
    o->intensityImage = mrpt::img::CImage(colour, mrpt::img::DEEP_COPY);
    o->cameraParams = cam.toMrpt();
    o->cameraParamsIntensity = cam.toMrpt();
    o->relativePoseIntensityWRTDepth =
        mrpt::poses::CPose3D(0, 0, 0, mrpt::DEG2RAD(-90.0), 0, mrpt::DEG2RAD(-90.0));
    return o;
}
}  // namespace smap::test
