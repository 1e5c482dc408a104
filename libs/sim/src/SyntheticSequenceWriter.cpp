#include "smap/sim/SyntheticSequenceWriter.h"

#include <mrpt/config/CConfigFileMemory.h>
#include <mrpt/core/format.h>
#include <mrpt/system/CTicTac.h>

#include <filesystem>
#include <fstream>
#include <map>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "smap/core/AtomicFile.h"
#include "smap/core/InputError.h"
#include "smap/core/JsonWriter.h"
#include "smap/core/LabelSet.h"
#include "smap/io/InputPreset.h"
#include "smap/io/TumTextFormats.h"

namespace fs = std::filesystem;

namespace smap::sim
{
namespace
{
void writePng(const fs::path& path, const cv::Mat& img)
{
    if (!cv::imwrite(path.string(), img))
        throw std::runtime_error("cannot write " + path.string());
}
}  // namespace

SyntheticSequenceWriter::SyntheticSequenceWriter() : COutputLogger("SyntheticSequenceWriter") {}

core::JsonValue SyntheticSequenceWriter::metaFor(const sim::SequenceGenerator& gen, size_t frames)
{
    const auto& o = gen.options();
    auto cam = core::JsonValue::object();
    cam.set("width", o.camera.width)
        .set("height", o.camera.height)
        .set("fx", o.camera.fx)
        .set("fy", o.camera.fy);
    cam.set("cx", o.camera.cx).set("cy", o.camera.cy);
    auto instances = core::JsonValue::array();
    for (const auto& [id, cls] : gen.scene().instanceClasses())
    {
        auto e = core::JsonValue::object();
        e.set("instance", static_cast<int>(id)).set("class", static_cast<int>(cls));
        instances.push(e);
    }
    auto meta = core::JsonValue::object();
    meta.set("generator", "smap-synth")
        .set("preset", gen.preset().name)
        .set("seed", static_cast<int64_t>(o.seed));
    meta.set("frames", static_cast<uint64_t>(frames)).set("fps", o.fps);
    meta.set("camera_motion", sim::toString(gen.preset().motion));
    meta.set("walking_people", gen.preset().walking).set("sitting_people", gen.preset().sitting);
    meta.set("camera", cam)
        .set("depth_factor", kDepthFactor)
        .set("noise_free_depth", o.noiseFreeDepth);
    meta.set("labels",
             "PASCAL VOC ids: 0 background, 9 chair, 11 diningtable, 15 person, 16 "
             "pottedplant, 18 sofa, 20 tvmonitor");
    meta.set("world_frame", "z up, floor at z = 0, metres");
    meta.set("instances", instances);
    return meta;
}

void SyntheticSequenceWriter::write(sim::SequenceGenerator& gen, size_t frames,
                                    const std::string& folder)
{
    write([&](size_t i) { return gen.frame(i); }, frames, metaFor(gen, frames),
          gen.options().camera, folder);
}

void SyntheticSequenceWriter::write(const FrameProducer& produce, size_t frames,
                                    const core::JsonValue& meta, const core::PinholeCamera& camera,
                                    const std::string& folder)
{
    const fs::path out(folder);
    const fs::path parent = out.parent_path().empty() ? fs::path(".") : out.parent_path();
    if (!fs::is_directory(parent))
        throw core::InputError(
            mrpt::format("output folder's parent '%s' does not exist", parent.c_str()));
    core::writeDirectoryAtomically(
        out.string(),
        [&](const std::string& tmpDir)
        {
            const fs::path tmp(tmpDir);
            for (const char* d : {"rgb", "depth", "labels", "instances", "dynamic", "objects"})
                fs::create_directories(tmp / d);
            std::ofstream rgbList(tmp / "rgb.txt"), depthList(tmp / "depth.txt"),
                assoc(tmp / "associations.txt");
            rgbList << "# colour images\n# timestamp filename\n";
            depthList << "# depth maps, 16-bit PNG, depth factor 5000 (0 = invalid)\n# timestamp "
                         "filename\n";
            core::Trajectory gt;
            std::map<std::string, core::Trajectory> objects;
            mrpt::system::CTicTac timer;
            double lastReport = 0.0;
            for (size_t i = 0; i < frames; i++)
            {
                const sim::SyntheticFrame f = produce(i);
                const std::string name = mrpt::format("%06zu.png", i);
                const std::string colourName =
                    mrpt::format(jpegQuality_ > 0 ? "%06zu.jpg" : "%06zu.png", i);
                if (!cv::imwrite((tmp / "rgb" / colourName).string(), f.rendered.colour,
                                 {cv::IMWRITE_JPEG_QUALITY, jpegQuality_ > 0 ? jpegQuality_ : 95}))
                    throw std::runtime_error("cannot write " + (tmp / "rgb" / colourName).string());
                cv::Mat depth16;
                f.rendered.depth.convertTo(depth16, CV_16UC1, kDepthFactor);
                writePng(tmp / "depth" / name, depth16);
                writePng(tmp / "labels" / name, f.rendered.labels);
                writePng(tmp / "instances" / name, f.rendered.instances);
                writePng(tmp / "dynamic" / name, f.rendered.dynamic);
                const std::string ts = mrpt::format("%.6f", f.timestamp);
                rgbList << ts << " rgb/" << colourName << "\n";
                depthList << ts << " depth/" << name << "\n";
                assoc << ts << " rgb/" << colourName << " " << ts << " depth/" << name << "\n";
                gt.push_back({f.timestamp, f.T_world_cam});
                for (const auto& [obj, pose] : f.objectPoses)
                    objects[obj].push_back({f.timestamp, pose});
                if (timer.Tac() - lastReport > 2.0)
                {
                    lastReport = timer.Tac();
                    MRPT_LOG_INFO_FMT("frame %zu / %zu (%.1f frames/s)", i + 1, frames,
                                      (i + 1) / lastReport);
                }
            }
            for (auto* s : {&rgbList, &depthList, &assoc})
            {
                s->close();
                if (s->fail())
                    throw std::runtime_error("cannot write the frame lists in " + tmp.string());
            }
            io::writeTumTrajectory((tmp / "groundtruth.txt").string(), gt,
                                   "ground truth T_world_cam (optical frame)");
            for (const auto& [obj, traj] : objects)
                io::writeTumTrajectory((tmp / "objects" / (obj + ".txt")).string(), traj,
                                       obj + " root pose (feet on the floor, z up)");

            {
                auto metaOut = meta;
                auto paths = core::JsonValue::array();
                for (const auto& [obj, traj] : objects)
                    paths.push(core::JsonValue::string("objects/" + obj + ".txt"));
                metaOut.set("object_trajectories", paths);
                core::AtomicTextFile f((tmp / "meta.json").string());
                f.stream() << metaOut.dump();
                f.commit();
            }
            {
                mrpt::config::CConfigFileMemory cfg;
                core::saveCamera(camera, cfg, "camera");
                cfg.write("tum", "depth_factor", kDepthFactor);
                std::string text;
                cfg.getContent(text);
                core::AtomicTextFile f((tmp / io::kFolderCameraFile).string());
                f.stream() << "# Written by smap-synth: how to read this folder. semantic-mapper, "
                              "smap-segment and\n# tum2rawlog load it when no [camera] is "
                              "configured.\n"
                           << text;
                f.commit();
            }
        },
        io::isSmapSynthOutput);  // the only kind of existing folder --out may replace
}

void writeContactSheet(const std::string& sequenceFolder, size_t count, const std::string& pngPath)
{
    const fs::path dir(sequenceFolder);
    std::vector<fs::path> frames;
    for (const auto& e : fs::directory_iterator(dir / "rgb"))
        frames.push_back(e.path().filename());
    std::sort(frames.begin(), frames.end());
    if (frames.empty())
        throw core::InputError("no frames in " + (dir / "rgb").string());
    count = std::min(count, frames.size());
    const int tw = 320, th = 240;
    cv::Mat sheet(th * static_cast<int>(count), tw * 4, CV_8UC3, cv::Scalar(0, 0, 0));
    const core::LabelSet classes = core::LabelSet::pascalVoc();  // what the generator labels
    for (size_t r = 0; r < count; r++)
    {
        const fs::path name = frames[r * (frames.size() - 1) / std::max<size_t>(1, count - 1)];
        const cv::Mat rgb = cv::imread((dir / "rgb" / name).string());
        const std::string png = name.stem().string() + ".png";
        const cv::Mat labels = cv::imread((dir / "labels" / png).string(), cv::IMREAD_UNCHANGED);
        const cv::Mat dyn = cv::imread((dir / "dynamic" / png).string(), cv::IMREAD_UNCHANGED);
        const cv::Mat depth = cv::imread((dir / "depth" / png).string(), cv::IMREAD_UNCHANGED);
        cv::Mat labelOverlay = rgb.clone(), dynOverlay = rgb.clone(), depthVis;
        for (int v = 0; v < rgb.rows; v++)
        {
            for (int u = 0; u < rgb.cols; u++)
            {
                const cv::Vec3b c = classes.colourOf(labels.at<uint8_t>(v, u));
                auto& p = labelOverlay.at<cv::Vec3b>(v, u);
                if (labels.at<uint8_t>(v, u) != 0 && labels.at<uint8_t>(v, u) != 255)
                    for (int k = 0; k < 3; k++)
                        p[k] = static_cast<uchar>((p[k] + 2 * c[k]) / 3);
                if (dyn.at<uint8_t>(v, u))
                    dynOverlay.at<cv::Vec3b>(v, u) = {0, 0, 255};
            }
        }
        cv::Mat d8;
        depth.convertTo(d8, CV_8UC1, 255.0 / (6.0 * SyntheticSequenceWriter::kDepthFactor));
        cv::applyColorMap(d8, depthVis, cv::COLORMAP_JET);
        depthVis.setTo(cv::Scalar(0, 0, 0), depth == 0);
        const cv::Mat tiles[4] = {rgb, labelOverlay, dynOverlay, depthVis};
        const char* captions[4] = {"colour", "labels (VOC)", "dynamic mask", "depth 0-6 m"};
        for (int c = 0; c < 4; c++)
        {
            cv::Mat small;
            cv::resize(tiles[c], small, {tw, th}, 0, 0, cv::INTER_AREA);
            cv::putText(small, captions[c] + std::string(" ") + name.stem().string(), {6, 18},
                        cv::FONT_HERSHEY_SIMPLEX, 0.5, cv::Scalar(255, 255, 255), 1, cv::LINE_AA);
            small.copyTo(sheet(cv::Rect(c * tw, static_cast<int>(r) * th, tw, th)));
        }
    }
    core::writeFileAtomically(pngPath, [&](const std::string& tmp) { writePng(tmp, sheet); });
}
}  // namespace smap::sim
