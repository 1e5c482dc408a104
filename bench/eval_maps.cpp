// The semantic maps on a rendered sequence with full ground truth: ground-truth
// poses and labels as the segmentation, dynamic points from the ground-truth dynamic mask (a
// perfect dynamic filter, 12 px grid), Algorithm 1, then every keyframe into both maps.
// Prints, for Algorithm 1 on and off:
//   - label accuracy: occupied octomap voxels whose fused class is the ground-truth majority
//     class of the static pixels (noise-free depth) that fell in them (or, for a voxel with
//     none, in its 26 neighbours);
//   - people in the map: occupied octomap voxels that people's pixels (ground-truth
//     instances) fell in at some keyframe and no static pixel ever did; and, as a second
//     view, occupied voxels whose fused class is person;
//   - geometry (with --noise-free): map points within 2 cm of the true surface (the
//     noise-free depth of static pixels, all frames);
//   - insertion time per keyframe (median) and memory of each map.
// With --espnet MODEL.onnx the labels come from ESPNetv2 + dense CRF instead of the ground
// truth. With --snapshots DIR, writes the map pictures. An evaluation program, not a test.
//
// Usage: eval_maps [--preset walking_xyz] [--frames 150] [--every 5] [--noise-free]
//                  [--espnet MODEL.onnx] [--snapshots DIR] [--grow-pixels N]
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <exception>
#include <iostream>
#include <map>
#include <opencv2/imgcodecs.hpp>
#include <string>
#include <unordered_map>
#include <vector>

#include "BenchStats.h"
#include "smap/apps/AppMain.h"
#include "smap/apps/CommandLine.h"
#include "smap/core/InputError.h"
#include "smap/core/LabelSet.h"
#include "smap/mapping/DynamicRegionFinder.h"
#include "smap/maps/CObservationSemanticRGBD.h"
#include "smap/maps/CSemanticOctoMap.h"
#include "smap/maps/CSemanticPointsMap.h"
#include "smap/maps/MapSnapshot.h"
#include "smap/segmentation/SegmentationParameters.h"
#include "smap/sim/SequenceGenerator.h"

using namespace smap;

namespace
{
double nowMs()
{
    return std::chrono::duration<double, std::milli>(
               std::chrono::steady_clock::now().time_since_epoch())
        .count();
}

int64_t cellKey(const Eigen::Vector3f& p, double size)
{
    const auto i = [&](float x) { return static_cast<int64_t>(std::floor(x / size)) + (1 << 20); };
    return i(p.x()) | (i(p.y()) << 21) | (i(p.z()) << 42);
}

struct Result
{
    maps::CSemanticPointsMap points;
    maps::CSemanticOctoMap octo;
    std::vector<double> pointsMs, octoMs, algorithmMs;
};
}  // namespace

const char* const kUsage =
    "Usage: eval_maps [--preset walking_xyz] [--frames 150] [--every 5] [--noise-free]\n"
    "                 [--espnet MODEL.onnx] [--snapshots DIR] [--grow-pixels N]\n"
    "\n"
    "Fills both semantic maps from a rendered sequence with full ground truth (ground-truth\n"
    "poses; labels from the ground truth or, with --espnet, ESPNetv2 + dense CRF), with and\n"
    "without Algorithm 1, and prints label accuracy, people left in the map, geometry,\n"
    "insertion time and memory. Exit codes: 0 ok, 1 internal error, 2 bad input.\n";

int run(int argc, char** argv)
{
    apps::CommandLine cl;
    cl.option("preset").option("frames").option("every").option("snapshots").option("espnet");
    cl.option("grow-pixels");
    cl.flag("noise-free").flag("help");
    cl.parse(std::vector<std::string>(argv + 1, argv + argc));
    if (cl.has("help"))
    {
        std::fputs(kUsage, stdout);
        return 0;
    }
    sim::GeneratorOptions o;
    o.preset = cl.value("preset").value_or("walking_xyz");
    o.noiseFreeDepth = cl.has("noise-free");
    const auto frames = static_cast<size_t>(cl.integer("frames", 150));
    const auto every = static_cast<size_t>(cl.integer("every", 5));
    sim::SequenceGenerator gen(o);
    const core::LabelSet labels = core::LabelSet::pascalVoc();
    mapping::DynamicRegionParameters regionParams;
    regionParams.grow_pixels =
        static_cast<int>(cl.integer("grow-pixels", regionParams.grow_pixels));
    const mapping::DynamicRegionFinder finder(regionParams, labels);

    // Ground truth per 5 cm voxel: votes of the static pixels' labels; the true surface as
    // 1 cm cells of the static pixels' noise-free points.
    std::unordered_map<int64_t, std::map<int, int>> votes;
    std::unordered_map<int64_t, std::vector<Eigen::Vector3f>> surface;
    // 5 cm voxels that people's pixels (ground-truth instances) fell in at some keyframe.
    std::unordered_map<int64_t, int> peopleCells;
    maps::BackProjector truthProjector{maps::BackProjectionParameters()};

    std::unique_ptr<segmentation::Segmenter> segmenter;
    if (const auto model = cl.value("espnet"))
    {
        segmentation::SegmentationParameters sp;
        sp.onnx.model = *model;
        segmenter = segmentation::makeSegmenter(sp);
        segmenter->setMinLoggingLevel(mrpt::system::LVL_WARN);
    }

    Result withAlgorithm, without;
    for (size_t i = 0; i < frames; i += every)
    {
        const auto f = gen.frame(i);
        const auto& r = f.rendered;
        // Ground truth from the noise-free depth (static pixels only).
        maps::BackProjector::Images truth{r.colour, f.depthNoiseFree, r.labels, cv::Mat(),
                                          r.dynamic};
        for (const auto& p : truthProjector.project(truth, o.camera, f.T_world_cam))
        {
            votes[cellKey(p.position, 0.05)][p.label]++;
            auto& cell = surface[cellKey(p.position, 0.01)];
            if (cell.size() < 4)
                cell.push_back(p.position);
        }
        cv::Mat people = r.labels == 15, notPeople = ~people;
        maps::BackProjector::Images personTruth{r.colour, f.depthNoiseFree, r.labels, cv::Mat(),
                                                notPeople};
        for (const auto& p : truthProjector.project(personTruth, o.camera, f.T_world_cam))
            peopleCells[cellKey(p.position, 0.05)]++;
        // The segmentation: ground truth (confidence 0.9) or the network.
        cv::Mat labelImage = r.labels;
        cv::Mat confidence(r.labels.size(), CV_32FC1, cv::Scalar(0.9f));
        if (segmenter)
        {
            core::RgbdFrame frame;
            frame.colour = r.colour;
            frame.depth = r.depth;
            frame.camera = o.camera;
            frame.name = std::to_string(i);
            const auto seg = segmenter->segment(frame);
            labelImage = seg.labels;
            confidence = seg.labelConfidence();
        }
        // Dynamic points: a perfect filter on a 12 px grid.
        std::vector<mapping::DynamicPoint> dynamicPoints;
        for (int v = 6; v < r.dynamic.rows; v += 12)
            for (int u = 6; u < r.dynamic.cols; u += 12)
                if (r.dynamic.at<uint8_t>(v, u))
                    dynamicPoints.push_back({double(u), double(v), 0.0});
        const double t0 = nowMs();
        const auto regions = finder.find(labelImage, r.depth, dynamicPoints);
        withAlgorithm.algorithmMs.push_back(nowMs() - t0);

        auto obs = maps::CObservationSemanticRGBD::Create();
        obs->camera = o.camera;
        obs->colour = r.colour;
        obs->depth = r.depth;
        obs->labels = labelImage;
        obs->confidence = confidence;
        for (auto [result, mask] :
             {std::pair{&withAlgorithm, regions.dynamicMask}, std::pair{&without, cv::Mat()}})
        {
            obs->dynamicMask = mask;
            double t = nowMs();
            result->points.insertObservation(*obs, f.T_world_cam);
            result->pointsMs.push_back(nowMs() - t);
            t = nowMs();
            result->octo.insertObservation(*obs, f.T_world_cam);
            result->octoMs.push_back(nowMs() - t);
        }
        std::fprintf(stderr, "\rframe %zu of %zu", i + 1, frames);
    }
    std::fprintf(stderr, "\n");

    std::printf(
        "%s, %zu keyframes (every %zu of %zu frames), %s depth, %s, ground-truth "
        "poses, dynamic points from the ground-truth mask\n",
        o.preset.c_str(), withAlgorithm.pointsMs.size(), every, frames,
        o.noiseFreeDepth ? "noise-free" : "noisy (Kinect model)",
        segmenter ? segmenter->description().c_str() : "ground-truth labels (confidence 0.9)");
    std::printf("Algorithm 1: median %.2f ms per keyframe\n",
                bench::median(withAlgorithm.algorithmMs));
    for (const auto& [name, res] :
         {std::pair{"Algorithm 1 on ", &withAlgorithm}, std::pair{"Algorithm 1 off", &without}})
    {
        const auto voxels = res->octo.occupiedVoxels();
        size_t judged = 0, correct = 0, person = 0, onPeople = 0;
        for (const auto& v : voxels)
        {
            person += v.label == 15;
            // On people: space that only people filled (no static surface in it).
            const int64_t key = cellKey(v.centre, 0.05);
            onPeople += peopleCells.count(key) && !votes.count(key);
            // The voxel's own votes; without any (depth noise put the surface one voxel off),
            // the votes of its 26 neighbours together.
            std::map<int, int> tally;
            if (const auto it = votes.find(cellKey(v.centre, 0.05)); it != votes.end())
                tally = it->second;
            for (int dx = -1; dx <= 1 && tally.empty(); dx++)
                for (int dy = -1; dy <= 1; dy++)
                    for (int dz = -1; dz <= 1; dz++)
                    {
                        const auto it = votes.find(
                            cellKey(v.centre + Eigen::Vector3f(dx, dy, dz) * 0.05f, 0.05));
                        if (it != votes.end())
                            for (const auto& [label, n] : it->second)
                                tally[label] += n;
                    }
            if (tally.empty())
                continue;
            const auto best =
                std::max_element(tally.begin(), tally.end(),
                                 [](const auto& a, const auto& b) { return a.second < b.second; });
            judged++;
            correct += best->first == v.label;
        }
        // Geometry: points-map points within 2 cm of a true surface point.
        size_t near = 0;
        const auto pts = res->points.points();
        for (const auto& p : pts)
        {
            bool found = false;
            for (int dx = -2; dx <= 2 && !found; dx++)
                for (int dy = -2; dy <= 2 && !found; dy++)
                    for (int dz = -2; dz <= 2 && !found; dz++)
                    {
                        const auto it = surface.find(
                            cellKey(p.position + Eigen::Vector3f(dx, dy, dz) * 0.01f, 0.01));
                        if (it == surface.end())
                            continue;
                        for (const auto& q : it->second)
                            found = found || (q - p.position).norm() <= 0.02f;
                    }
            near += found;
        }
        std::printf(
            "%s: octomap %zu occupied voxels, label accuracy %.2f%% (%zu with ground truth), "
            "on people %.2f%% (labelled person %.2f%%); points map %zu points, within 2 cm of "
            "the true surface %.2f%%\n",
            name, voxels.size(), 100.0 * correct / std::max<size_t>(1, judged), judged,
            100.0 * onPeople / std::max<size_t>(1, voxels.size()),
            100.0 * person / std::max<size_t>(1, voxels.size()), pts.size(),
            100.0 * near / std::max<size_t>(1, pts.size()));
        std::printf(
            "    insertion per keyframe (median): points map %.2f ms (%.3f m voxels), "
            "octomap %.2f ms (%.3f m); memory: points map %.1f MB, octomap %.1f MB\n",
            bench::median(res->pointsMs), res->points.insertionOptions.voxel_size,
            bench::median(res->octoMs), res->octo.insertionOptions.resolution,
            res->points.memoryBytes() / 1048576.0, res->octo.memoryBytes() / 1048576.0);
    }
    if (const auto dir = cl.value("snapshots"))
    {
        maps::MapSnapshot snap;
        cv::imwrite(*dir + "/points_by_class.png", snap.render(withAlgorithm.points));
        cv::imwrite(*dir + "/octomap_by_class.png", snap.render(withAlgorithm.octo));
        withAlgorithm.octo.renderOptions.colour_by_class = false;
        cv::imwrite(*dir + "/octomap_by_rgb.png", snap.render(withAlgorithm.octo));
        without.octo.renderOptions.colour_by_class = true;
        cv::imwrite(*dir + "/octomap_by_class_without_algorithm1.png", snap.render(without.octo));
        std::printf("snapshots written to %s\n", dir->c_str());
    }
    return 0;
}

int main(int argc, char** argv)
{
    return smap::apps::runGuarded("eval_maps", std::cerr, [&] { return run(argc, argv); });
}
