// Peer baseline: OpenCV's RGB-D odometry (opencv_contrib rgbd module, cv::rgbd::RgbdOdometry,
// Steinbruecker et al.'s photometric + depth term), frame to frame, on exactly the frames
// semantic-mapper sees: read through our FrameSource with the same configuration, so the depth
// is registered to the colour camera wherever ours is. Writes a TUM trajectory to score with
// smap-eval. A benchmark tool, not part of the app.
//
// --export DIR also writes the frames as read (colour PNG, depth PNG at 5000 units per metre,
// associations.txt) for peers that read TUM folders themselves (bench/open3d_rgbd_odometry.py).
//
// Usage: peer_rgbd_odometry INPUT OUT.txt [--config FILE]... [--set S.K=V]... [--max-frames N]
//                           [--export DIR]
#include <mrpt/core/format.h>
#include <mrpt/math/CMatrixFixed.h>
#include <mrpt/poses/CPose3D.h>

#include <Eigen/Geometry>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <limits>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <opencv2/rgbd.hpp>
#include <optional>
#include <string>
#include <vector>

#include "smap/apps/AppConfiguration.h"
#include "smap/apps/AppMain.h"
#include "smap/apps/CommandLine.h"
#include "smap/core/InputError.h"
#include "smap/core/Trajectory.h"
#include "smap/io/FrameSource.h"
#include "smap/io/TumTextFormats.h"

using namespace smap;

namespace
{
const char* const kUsage =
    "Usage: peer_rgbd_odometry INPUT OUT.txt [--config FILE]... [--set S.K=V]... "
    "[--max-frames N] [--export DIR]\n"
    "\n"
    "OpenCV's RgbdOdometry (rgbd module), frame to frame, over the frames semantic-mapper reads\n"
    "from INPUT with the same configuration (a TUM folder's preset applies as it does there, so\n"
    "7-Scenes depth is registered to its colour camera). Writes OUT.txt (TUM format). Exit\n"
    "codes: 0 ok, 1 internal error, 2 bad input.\n"
    "  --export DIR  also write the frames as read into DIR (TUM layout: rgb/ and depth/ PNGs,\n"
    "                depth at 5000 units per metre, associations.txt), the same input for\n"
    "                peers that read folders (bench/open3d_rgbd_odometry.py DIR ... \n"
    "                --depth-factor 5000)\n";

/// Writes frame `f` into the TUM folder `dir` and its line into `associations`.
void exportFrame(const core::RgbdFrame& f, const std::string& dir, std::ostream& associations)
{
    const std::string name = mrpt::format("%06zu.png", f.index);
    cv::Mat depth16;
    f.depth.convertTo(depth16, CV_16U, 5000.0);  // rounds to the nearest 0.2 mm
    if (!cv::imwrite(dir + "/rgb/" + name, f.colour) ||
        !cv::imwrite(dir + "/depth/" + name, depth16))
        throw core::InputError("cannot write into --export folder '" + dir + "'");
    associations << mrpt::format("%.6f rgb/%s %.6f depth/%s\n", f.timestamp, name.c_str(),
                                 f.timestamp, name.c_str());
}

Eigen::Isometry3d toIsometry(const cv::Mat& Rt)
{
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    for (int r = 0; r < 3; r++)
    {
        for (int c = 0; c < 3; c++)
            T.linear()(r, c) = Rt.at<double>(r, c);
        T.translation()[r] = Rt.at<double>(r, 3);
    }
    return T;
}

struct OdometryFrame
{
    cv::Mat grey;   ///< CV_8UC1
    cv::Mat depth;  ///< CV_32FC1 metres, NaN where invalid (what the rgbd module expects)
};

OdometryFrame prepare(const core::RgbdFrame& f)
{
    OdometryFrame o;
    cv::cvtColor(f.colour, o.grey, cv::COLOR_BGR2GRAY);
    o.depth = f.depth.clone();
    o.depth.setTo(std::numeric_limits<float>::quiet_NaN(), f.depth <= 0.0F);
    return o;
}

int run(const std::vector<std::string>& args)
{
    apps::CommandLine cl;
    cl.option("config").option("set").option("max-frames").option("export").flag("help");
    cl.parse(args);
    if (cl.has("help"))
    {
        std::cout << kUsage;
        return apps::kExitOk;
    }
    if (cl.positionals().size() != 2)
        throw core::InputError("peer_rgbd_odometry needs INPUT and OUT.txt (see --help)");
    const std::string input = cl.positionals()[0];
    const std::string outPath = cl.positionals()[1];
    io::FrameSourceParameters params;
    mrpt::system::COutputLogger log("peer_rgbd_odometry");
    apps::loadAppConfiguration(cl, {&params}, input, log);
    params.max_frames = static_cast<size_t>(cl.integer("max-frames", 0));
    auto source = io::openFrameSource(input, params);
    source->setMinLoggingLevel(mrpt::system::LVL_WARN);
    const std::string exportDir = cl.value("export").value_or("");
    std::ofstream associations;
    if (!exportDir.empty())
    {
        std::filesystem::create_directories(exportDir + "/rgb");
        std::filesystem::create_directories(exportDir + "/depth");
        associations.open(exportDir + "/associations.txt");
    }

    core::Trajectory trajectory;
    std::optional<OdometryFrame> previous;
    cv::Ptr<cv::rgbd::RgbdOdometry> odometry;
    Eigen::Isometry3d T_world_cam = Eigen::Isometry3d::Identity();
    size_t frames = 0, failures = 0;
    while (auto f = source->next())
    {
        if (!exportDir.empty())
            exportFrame(*f, exportDir, associations);
        OdometryFrame current = prepare(*f);
        if (!odometry)
        {
            cv::Mat K;
            f->camera.cameraMatrix().convertTo(K, CV_32F);
            odometry = cv::makePtr<cv::rgbd::RgbdOdometry>(K);
        }
        if (previous)
        {
            // Rt maps points of the source (previous) frame into the destination (current).
            // Started from no motion: a constant-velocity start tracked 7-Scenes worse
            // (docs/tracking.md).
            cv::Mat Rt;
            const cv::Mat noMask;
            if (odometry->compute(previous->grey, previous->depth, noMask, current.grey,
                                  current.depth, noMask, Rt))
                T_world_cam = T_world_cam * toIsometry(Rt).inverse();
            else
                failures++;  // keep the last pose (a camera at rest)
        }
        mrpt::math::CMatrixDouble44 M;
        M.asEigen() = T_world_cam.matrix();
        trajectory.push_back({f->timestamp, mrpt::poses::CPose3D(M)});
        previous = std::move(current);
        if (++frames % 200 == 0)
            std::fprintf(stderr, "%zu frames\n", frames);
    }
    io::writeTumTrajectory(outPath, trajectory, "OpenCV RgbdOdometry on " + input);
    std::printf("%zu frames, %zu odometry failures (pose kept), trajectory in %s\n", frames,
                failures, outPath.c_str());
    return apps::kExitOk;
}
}  // namespace

int main(int argc, char** argv)
{
    return smap::apps::runGuarded("peer_rgbd_odometry", std::cerr,
                                  [&] {
                                      return run({argv + 1, argv + argc});
                                  });
}
