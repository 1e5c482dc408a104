// One bad frame must not cost a run: semantic-mapper on small copies of a real folder (the first
// 30 frames of 7-Scenes; a rendered folder when ../shared is absent) and of the sample rawlog,
// each damaged in one way. Unreadable frames are skipped (exit 0, a pose for every readable
// frame, frames.csv and metrics.json say which), input that is no recording is refused (exit 2,
// naming the file). Never a signal, never a hang, never a half-written output.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <functional>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "CliHelpers.h"
#include "TestData.h"

namespace fs = std::filesystem;
using smap::test::bin;
using smap::test::CmdResult;
using smap::test::jsonNumber;
using smap::test::run;

namespace
{
constexpr int kFrames = 30;

/// The first kFrames frames of 7-Scenes (a folder named so that its preset applies), or a
/// rendered static sequence at 320x240 when ../shared is absent. Made once per test program.
const std::string& pristineFolder()
{
    static const std::string folder = []
    {
        static const smap::test::TempDir scratch;  // removed when the program ends
        const fs::path root = scratch.str();
        const fs::path seven = smap::test::sevenScenesDir();
        if (!fs::exists(seven / "associations.txt"))
        {
            const fs::path out = root / "rendered";
            const auto r =
                run(bin("smap-synth") + " --preset static_xyz --frames " + std::to_string(kFrames) +
                    " --size 320x240 --no-rawlog " + "--contact-sheet 0 --out " + out.string());
            EXPECT_EQ(r.code, 0) << r.output;
            return out.string();
        }
        const fs::path out = root / "7scenes-redkitchen-30";
        fs::create_directories(out / "rgb");
        fs::create_directories(out / "depth");
        std::ifstream in(seven / "associations.txt");
        std::ofstream assoc(out / "associations.txt");
        std::string line;
        for (int n = 0; n < kFrames && std::getline(in, line);)
        {
            if (line.empty() || line[0] == '#')
                continue;
            assoc << line << "\n";
            std::istringstream fields(line);
            std::string t1, rgb, t2, depth;
            fields >> t1 >> rgb >> t2 >> depth;
            fs::copy_file(seven / rgb, out / rgb);
            fs::copy_file(seven / depth, out / depth);
            n++;
        }
        fs::copy_file(seven / "groundtruth_sfm.txt", out / "groundtruth.txt");
        return out.string();
    }();
    return folder;
}

/// The i-th (0-based) data line's colour and depth files of a folder's associations.txt.
std::pair<std::string, std::string> imagesOf(const std::string& folder, int i)
{
    std::ifstream in(fs::path(folder) / "associations.txt");
    std::string line;
    for (int n = 0; std::getline(in, line);)
    {
        if (line.empty() || line[0] == '#')
            continue;
        if (n++ == i)
        {
            std::istringstream fields(line);
            std::string t1, rgb, t2, depth;
            fields >> t1 >> rgb >> t2 >> depth;
            return {(fs::path(folder) / rgb).string(), (fs::path(folder) / depth).string()};
        }
    }
    ADD_FAILURE() << "no line " << i << " in " << folder;
    return {};
}

/// A copy of the pristine folder in `dir`, damaged by `damage`.
std::string damagedCopy(const smap::test::TempDir& dir,
                        const std::function<void(const std::string&)>& damage)
{
    const fs::path copy = fs::path(dir.str()) / fs::path(pristineFolder()).filename();
    fs::copy(pristineFolder(), copy, fs::copy_options::recursive);
    damage(copy.string());
    return copy.string();
}

struct Outcome
{
    CmdResult cmd;
    std::string metrics, frames, trajectory;
    fs::path out;
};

/// semantic-mapper on `input` (no segmentation: reading is what is tested), under a time limit.
Outcome runMapper(const smap::test::TempDir& dir, const std::string& input)
{
    Outcome o;
    o.out = fs::path(dir.str()) / "out";
    o.cmd = run("timeout 300 " + bin("semantic-mapper") + " '" + input + "' --out " +
                o.out.string() + " --set segmentation.backend=none --set output.snapshots=false");
    o.metrics = smap::test::readTextFile((o.out / "metrics.json").string());
    o.frames = smap::test::readTextFile((o.out / "frames.csv").string());
    o.trajectory = smap::test::readTextFile((o.out / "trajectory.txt").string());
    return o;
}

/// No temporary file or folder left in the output (each output is renamed when complete).
void expectNoPartialOutput(const fs::path& out)
{
    if (!fs::exists(out))
        return;
    for (const auto& e : fs::recursive_directory_iterator(out))
        EXPECT_EQ(e.path().filename().string().find(".tmp-"), std::string::npos)
            << "left behind: " << e.path();
}

size_t lines(const std::string& text, const std::string& containing = "")
{
    size_t n = 0;
    std::istringstream in(text);
    for (std::string line; std::getline(in, line);)
        n += !line.empty() && line[0] != '#' && line.find(containing) != std::string::npos;
    return n;
}

/// A run that skipped `skipped` frames and went on: exit 0, a pose for every readable frame,
/// the skipped frames in frames.csv and metrics.json, the file named in a warning.
void expectSkippedAndTracked(const Outcome& o, size_t skipped, const std::string& file,
                             size_t total = kFrames)
{
    EXPECT_EQ(o.cmd.code, 0) << o.cmd.output;
    EXPECT_NE(o.cmd.output.find(file), std::string::npos) << "names " << file << "\n"
                                                          << o.cmd.output;
    EXPECT_EQ(jsonNumber(o.metrics, {"frames_skipped"}), static_cast<double>(skipped));
    EXPECT_EQ(jsonNumber(o.metrics, {"frames"}), static_cast<double>(total - skipped));
    EXPECT_EQ(jsonNumber(o.metrics, {"tracking", "frames_with_pose"}),
              static_cast<double>(total - skipped))
        << o.metrics;
    EXPECT_EQ(lines(o.trajectory), total - skipped);
    EXPECT_EQ(lines(o.frames, ",skipped,"), skipped) << o.frames;
    EXPECT_EQ(lines(o.frames) - 1, total) << "every frame has its row";
    expectNoPartialOutput(o.out);
}

/// Input that is no recording: exit 2 and an error naming `file`.
void expectRefused(const Outcome& o, const std::string& file)
{
    EXPECT_EQ(o.cmd.code, 2) << o.cmd.output;
    EXPECT_NE(o.cmd.output.find("error: "), std::string::npos) << o.cmd.output;
    EXPECT_NE(o.cmd.output.find(file), std::string::npos) << "names " << file << "\n"
                                                          << o.cmd.output;
    expectNoPartialOutput(o.out);
}

void writeBytes(const std::string& path, const std::string& bytes)
{
    std::ofstream(path, std::ios::binary | std::ios::trunc) << bytes;
}

enum class Image
{
    Colour,
    Depth
};

/// Damages one image of frame `index` in a copy of the folder with `damage`, runs the mapper and
/// checks that exactly that frame is skipped, with the file and `reason` in frames.csv.
void expectOneImageSkipped(Image which, int index,
                           const std::function<void(const std::string&)>& damage,
                           const std::string& reason)
{
    smap::test::TempDir dir;
    std::string file;
    const auto folder = damagedCopy(dir,
                                    [&](const std::string& f)
                                    {
                                        const auto images = imagesOf(f, index);
                                        file =
                                            which == Image::Colour ? images.first : images.second;
                                        damage(file);
                                    });
    const auto o = runMapper(dir, folder);
    expectSkippedAndTracked(o, 1, file);
    EXPECT_NE(o.frames.find(file + ": " + reason), std::string::npos) << o.frames;
}
}  // namespace

TEST(BadFrames, MissingColourImageIsSkipped)
{
    expectOneImageSkipped(
        Image::Colour, 10, [](const std::string& rgb) { fs::remove(rgb); }, "colour image missing");
}

TEST(BadFrames, TruncatedDepthPngIsSkipped)
{
    expectOneImageSkipped(
        Image::Depth, 12, [](const std::string& depth) { fs::resize_file(depth, 300); },
        "depth image cannot be decoded");
}

TEST(BadFrames, ZeroByteColourFileIsSkipped)
{
    expectOneImageSkipped(
        Image::Colour, 14, [](const std::string& rgb) { fs::resize_file(rgb, 0); },
        "colour image empty (0 bytes)");
}

TEST(BadFrames, DepthImageOfTheWrongSizeIsSkipped)
{
    expectOneImageSkipped(
        Image::Depth, 16,
        [](const std::string& depth)
        {
            const cv::Mat d = cv::imread(depth, cv::IMREAD_UNCHANGED);
            cv::Mat half;
            cv::resize(d, half, {d.cols / 2, d.rows / 2}, 0, 0, cv::INTER_NEAREST);
            ASSERT_TRUE(cv::imwrite(depth, half));
        },
        "depth image is ");
}

TEST(BadFrames, AllZeroDepthFramesAreSkipped)
{
    smap::test::TempDir dir;
    std::vector<std::string> depths;
    const auto folder = damagedCopy(dir,
                                    [&](const std::string& f)
                                    {
                                        for (int i = 20; i < 23; i++)
                                        {
                                            depths.push_back(imagesOf(f, i).second);
                                            cv::Mat d =
                                                cv::imread(depths.back(), cv::IMREAD_UNCHANGED);
                                            d.setTo(0);
                                            ASSERT_TRUE(cv::imwrite(depths.back(), d));
                                        }
                                    });
    const auto o = runMapper(dir, folder);
    expectSkippedAndTracked(o, 3, depths[0]);
    EXPECT_NE(o.frames.find(depths[2] + ": depth image holds no valid depth"), std::string::npos);
}

TEST(BadFrames, GarbageLineInTheListIsLeftOut)
{
    smap::test::TempDir dir;
    const auto folder = damagedCopy(dir,
                                    [](const std::string& f)
                                    {
                                        const fs::path list = fs::path(f) / "associations.txt";
                                        std::string text = smap::test::readTextFile(list);
                                        text.insert(0, "1.2.3 this is no list line\n");
                                        writeBytes(list.string(), text);
                                    });
    const auto o = runMapper(dir, folder);
    // The line names no frame: every listed frame is read, the line is named in a warning.
    expectSkippedAndTracked(o, 0, (fs::path(folder) / "associations.txt").string() + ":1:");
}

TEST(BadFrames, EmptyListIsRefusedNamingIt)
{
    smap::test::TempDir dir;
    const auto folder =
        damagedCopy(dir, [](const std::string& f) { writeBytes(f + "/associations.txt", ""); });
    const auto o = runMapper(dir, folder);
    expectRefused(o, (fs::path(folder) / "associations.txt").string());
    EXPECT_NE(o.cmd.output.find("lists no frames"), std::string::npos) << o.cmd.output;
}

TEST(BadFrames, FolderThatIsNoDataSetIsRefused)
{
    smap::test::TempDir dir;
    const std::string folder = dir / "holiday-photos";
    fs::create_directories(folder);
    writeBytes(folder + "/beach.jpg", "not even a picture");
    const auto o = runMapper(dir, folder);
    expectRefused(o, folder);
    EXPECT_NE(o.cmd.output.find("is not a TUM RGB-D folder"), std::string::npos) << o.cmd.output;
}

TEST(BadFrames, RandomBytesNamedRawlogAreRefused)
{
    smap::test::TempDir dir;
    std::mt19937 rng(7);
    std::string bytes(20000, '\0');
    for (auto& b : bytes)
        b = static_cast<char>(rng() & 0xFF);
    const std::string rawlog = dir / "recording.rawlog";
    writeBytes(rawlog, bytes);
    const auto o = runMapper(dir, rawlog);
    expectRefused(o, rawlog);
}

TEST(BadFrames, SampleRawlogCutShortKeepsEveryFrameBeforeTheCut)
{
    // An interrupted recording: the sample rawlog (gzip) cut at 60 % of its bytes, beside its
    // images folder and ground truth as the recorder left them.
    smap::test::TempDir dir;
    const fs::path sample = smap::test::sourceDir() + "/rawlogs/sample_walking_xyz.rawlog";
    const std::string rawlog = dir / "sample_walking_xyz.rawlog";
    fs::copy_file(sample, rawlog);
    fs::resize_file(rawlog, fs::file_size(sample) * 6 / 10);
    fs::create_directory_symlink(fs::path(sample).replace_filename("sample_walking_xyz_Images"),
                                 dir / "sample_walking_xyz_Images");
    const auto o = runMapper(dir, rawlog);
    EXPECT_EQ(o.cmd.code, 0) << o.cmd.output;
    EXPECT_NE(o.cmd.output.find("rawlog '" + rawlog + "' is damaged or cut short at entry"),
              std::string::npos)
        << o.cmd.output;
    const double frames = jsonNumber(o.metrics, {"frames"});
    EXPECT_GT(frames, 100.0) << "about 60 % of the 200 frames come before the cut";
    EXPECT_LT(frames, 130.0);
    EXPECT_EQ(jsonNumber(o.metrics, {"tracking", "frames_with_pose"}), frames) << o.metrics;
    EXPECT_EQ(static_cast<double>(lines(o.trajectory)), frames);
    EXPECT_NE(o.metrics.find("\"input_ended_early\": \"rawlog '"), std::string::npos) << o.metrics;
    for (const char* f : {"semantic_map.bin", "semantic_points.ply", "semantic_octomap.ot",
                          "annotated.rawlog", "keyframes.txt", "frames.csv"})
        EXPECT_TRUE(fs::exists(o.out / f)) << f;
    expectNoPartialOutput(o.out);
}

TEST(BadFrames, MostFramesUnreadableMakesTheRunBadInput)
{
    // 20 of 30 colour images gone: the outputs cover the 10 readable frames, the exit code says
    // that the recording is damaged.
    smap::test::TempDir dir;
    const auto folder = damagedCopy(dir,
                                    [](const std::string& f)
                                    {
                                        for (int i = 5; i < 25; i++)
                                            fs::remove(imagesOf(f, i).first);
                                    });
    const auto o = runMapper(dir, folder);
    EXPECT_EQ(o.cmd.code, 2) << o.cmd.output;
    EXPECT_NE(o.cmd.output.find("20 of the 30 frames"), std::string::npos) << o.cmd.output;
    EXPECT_NE(o.cmd.output.find("max_skipped_fraction"), std::string::npos) << o.cmd.output;
    EXPECT_EQ(jsonNumber(o.metrics, {"frames_skipped"}), 20.0) << o.metrics;
    EXPECT_EQ(lines(o.frames, ",skipped,"), 20u);
    expectNoPartialOutput(o.out);
}
