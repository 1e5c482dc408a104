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

/// The frame's images below `dir` (rgb/, depth/, labels/, instances/, dynamic/); returns the
/// colour file's name (PNG, or JPEG at `jpegQuality` when > 0).
std::string writeFrameImages(const fs::path& dir, size_t i, const sim::SyntheticFrame& f,
                             int jpegQuality, double depthFactor)
{
    const std::string name = mrpt::format("%06zu.png", i);
    std::string colourName = mrpt::format(jpegQuality > 0 ? "%06zu.jpg" : "%06zu.png", i);
    if (!cv::imwrite((dir / "rgb" / colourName).string(), f.rendered.colour,
                     {cv::IMWRITE_JPEG_QUALITY, jpegQuality > 0 ? jpegQuality : 95}))
        throw std::runtime_error("cannot write " + (dir / "rgb" / colourName).string());
    cv::Mat depth16;
    f.rendered.depth.convertTo(depth16, CV_16UC1, depthFactor);
    writePng(dir / "depth" / name, depth16);
    writePng(dir / "labels" / name, f.rendered.labels);
    writePng(dir / "instances" / name, f.rendered.instances);
    writePng(dir / "dynamic" / name, f.rendered.dynamic);
    return colourName;
}

/// rgb.txt, depth.txt and associations.txt, as TUM's tools write them.
class FrameLists
{
public:
    explicit FrameLists(const fs::path& dir)
        : dir_(dir),
          rgb_(dir / "rgb.txt"),
          depth_(dir / "depth.txt"),
          assoc_(dir / "associations.txt")
    {
        rgb_ << "# colour images\n# timestamp filename\n";
        depth_ << "# depth maps, 16-bit PNG, depth factor 5000 (0 = invalid)\n# timestamp "
                  "filename\n";
    }
    void add(double timestamp, const std::string& colourName, size_t i)
    {
        const std::string name = mrpt::format("%06zu.png", i);
        const std::string ts = mrpt::format("%.6f", timestamp);
        rgb_ << ts << " rgb/" << colourName << "\n";
        depth_ << ts << " depth/" << name << "\n";
        assoc_ << ts << " rgb/" << colourName << " " << ts << " depth/" << name << "\n";
    }
    void close()
    {
        for (auto* s : {&rgb_, &depth_, &assoc_})
        {
            s->close();
            if (s->fail())
                throw std::runtime_error("cannot write the frame lists in " + dir_.string());
        }
    }

private:
    fs::path dir_;
    std::ofstream rgb_, depth_, assoc_;
};

void writeMeta(const fs::path& dir, core::JsonValue meta,
               const std::map<std::string, core::Trajectory>& objects)
{
    auto paths = core::JsonValue::array();
    for (const auto& [obj, traj] : objects)
        paths.push(core::JsonValue::string("objects/" + obj + ".txt"));
    meta.set("object_trajectories", paths);
    core::AtomicTextFile f((dir / "meta.json").string());
    f.stream() << meta.dump();
    f.commit();
}

/// camera.ini: how to read the folder (its camera and depth factor).
void writeFolderCamera(const fs::path& dir, const core::PinholeCamera& camera, double depthFactor)
{
    mrpt::config::CConfigFileMemory cfg;
    core::saveCamera(camera, cfg, "camera");
    cfg.write("tum", "depth_factor", depthFactor);
    std::string text;
    cfg.getContent(text);
    core::AtomicTextFile f((dir / io::kFolderCameraFile).string());
    f.stream() << "# Written by smap-synth: how to read this folder. semantic-mapper, "
                  "smap-segment and\n# tum2rawlog load it when no [camera] is "
                  "configured.\n"
               << text;
    f.commit();
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
            std::map<std::string, core::Trajectory> objects;
            writeFrames(produce, frames, tmp, objects);
            for (const auto& [obj, traj] : objects)
                io::writeTumTrajectory((tmp / "objects" / (obj + ".txt")).string(), traj,
                                       obj + " root pose (feet on the floor, z up)");
            writeMeta(tmp, meta, objects);
            writeFolderCamera(tmp, camera, kDepthFactor);
        },
        io::isSmapSynthOutput);  // the only kind of existing folder --out may replace
}

void SyntheticSequenceWriter::writeFrames(const FrameProducer& produce, size_t frames,
                                          const std::string& folder,
                                          std::map<std::string, core::Trajectory>& objects)
{
    const fs::path dir(folder);
    FrameLists lists(dir);
    core::Trajectory gt;
    mrpt::system::CTicTac timer;
    double lastReport = 0.0;
    for (size_t i = 0; i < frames; i++)
    {
        const sim::SyntheticFrame f = produce(i);
        lists.add(f.timestamp, writeFrameImages(dir, i, f, jpegQuality_, kDepthFactor), i);
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
    lists.close();
    io::writeTumTrajectory((dir / "groundtruth.txt").string(), gt,
                           "ground truth T_world_cam (optical frame)");
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
