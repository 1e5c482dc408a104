#include "smap/pipeline/EvalApp.h"

#include <mrpt/core/format.h>

#include <algorithm>
#include <filesystem>
#include <optional>
#include <vector>

#include "smap/core/AtomicFile.h"
#include "smap/core/InputError.h"
#include "smap/eval/EvalReport.h"
#include "smap/eval/KeypointDetectionScore.h"
#include "smap/eval/TrajectoryPlot.h"
#include "smap/io/TumTextFormats.h"
#include "smap/pipeline/CommandLine.h"

namespace smap::pipeline
{
namespace
{
void writeJson(const std::string& path, const core::JsonValue& j)
{
    core::AtomicTextFile f(path);
    f.stream() << j.dump();
    f.commit();
}

/// smap-eval keypoints: every DEBUG_DIR/*.csv against MASK_DIR/<same stem>.png.
int scoreKeypoints(const std::string& maskDir, const std::string& debugDir,
                   const std::optional<std::string>& json, std::ostream& out)
{
    namespace fs = std::filesystem;
    if (!fs::is_directory(maskDir) || !fs::is_directory(debugDir))
        throw core::InputError(
            mrpt::format("'%s' and '%s' must both be folders", maskDir.c_str(), debugDir.c_str()));
    std::vector<fs::path> tables;
    for (const auto& e : fs::directory_iterator(debugDir))
        if (e.path().extension() == ".csv")
            tables.push_back(e.path());
    std::sort(tables.begin(), tables.end());
    if (tables.empty())
        throw core::InputError("'" + debugDir +
                               "' has no keypoint tables (run semantic-mapper --dynamic-debug)");
    eval::KeypointDetectionScore total;
    for (const auto& t : tables)
    {
        const fs::path mask = fs::path(maskDir) / (t.stem().string() + ".png");
        if (!fs::exists(mask))
            throw core::InputError(mrpt::format("'%s' has no ground-truth mask '%s'",
                                                t.string().c_str(), mask.string().c_str()));
        total += eval::scoreKeypointFrame(t.string(), mask.string());
    }
    out << mrpt::format("frames %zu  recall %.4f  precision %.4f  (tp %zu fp %zu fn %zu tn %zu)\n",
                        total.frames, total.recall(), total.precision(), total.truePositives,
                        total.falsePositives, total.falseNegatives, total.trueNegatives);
    if (json)
        writeJson(*json, total.toJson());
    return kExitOk;
}

int parseAxis(char c)
{
    if (c < 'x' || c > 'z')
        throw core::InputError(mrpt::format("--axes: '%c' is not x, y or z", c));
    return c - 'x';
}
}  // namespace

std::string EvalApp::usage()
{
    return "Usage:\n"
           "  smap-eval ate GT EST [--json FILE] [--plot FILE.png] [--axes xy] [--max-dt S]\n"
           "                       [--offset S] [--scale]\n"
           "  smap-eval rpe GT EST [--delta D] [--delta-unit s|frames] [--json FILE] [--max-dt S]\n"
           "                       [--offset S]\n"
           "  smap-eval keypoints MASK_DIR DEBUG_DIR [--json FILE]\n"
           "\n"
           "keypoints: dynamic-keypoint recall and precision of semantic-mapper --dynamic-debug\n"
           "  tables (DEBUG_DIR/NNNNNN.csv) against ground-truth masks (MASK_DIR/NNNNNN.png,\n"
           "  e.g. the dynamic/ folder smap-synth writes).\n"
           "GT and EST are TUM trajectory files (timestamp tx ty tz qx qy qz qw).\n"
           "  --max-dt S    association tolerance in seconds (default 0.02)\n"
           "  --offset S    added to EST timestamps before association (default 0)\n"
           "  --scale       ATE: Sim(3) alignment (monocular-style); default SE(3)\n"
           "  --plot F.png  ATE: top view of ground truth, estimate and difference\n"
           "  --axes AB     ATE plot axes, e.g. xy or xz (default: the two of largest extent)\n"
           "  --delta D     RPE interval (default 1); --delta-unit s (default) or frames\n"
           "  --json FILE   write the numbers as JSON (rmse, mean, median, std, min, max, ...)\n"
           "Conventions: docs/evaluation.md. Exit codes: 0 ok, 1 internal error, 2 bad input.\n";
}

int EvalApp::run(const std::vector<std::string>& args, std::ostream& out)
{
    CommandLine cl;
    cl.option("json").option("plot").option("axes").option("max-dt").option("offset");
    cl.option("delta").option("delta-unit").flag("scale").flag("help");
    cl.parse(args);
    if (cl.has("help"))
    {
        out << usage();
        return kExitOk;
    }
    const auto& pos = cl.positionals();
    if (pos.size() != 3 || (pos[0] != "ate" && pos[0] != "rpe" && pos[0] != "keypoints"))
        throw core::InputError(
            "expected 'smap-eval ate GT EST', 'smap-eval rpe GT EST' or "
            "'smap-eval keypoints MASK_DIR DEBUG_DIR' (see --help)");
    if (pos[0] == "keypoints")
        return scoreKeypoints(pos[1], pos[2], cl.value("json"), out);
    const auto gt = io::readTumTrajectory(pos[1]);
    const auto est = io::readTumTrajectory(pos[2]);

    if (pos[0] == "ate")
    {
        if (cl.has("delta") || cl.has("delta-unit"))
            throw core::InputError("--delta and --delta-unit apply to 'rpe' only");
        eval::AteOptions o;
        o.maxDifference = cl.number("max-dt", o.maxDifference);
        o.offset = cl.number("offset", o.offset);
        o.withScale = cl.has("scale");
        const auto r = eval::computeAte(gt, est, o);
        out << eval::ateToText(r);
        if (const auto j = cl.value("json"))
            writeJson(*j, eval::ateToJson(r, o));
        if (const auto p = cl.value("plot"))
        {
            eval::PlotOptions po;
            po.title = "ATE: " + std::filesystem::path(pos[2]).filename().string() + " vs " +
                       std::filesystem::path(pos[1]).filename().string();
            if (const auto a = cl.value("axes"))
            {
                if (a->size() != 2)
                    throw core::InputError(
                        mrpt::format("--axes '%s': give two of x, y, z", a->c_str()));
                po.horizontalAxis = parseAxis((*a)[0]);
                po.verticalAxis = parseAxis((*a)[1]);
            }
            eval::saveAtePlot(*p, r, po);
            out << "plot written to " << *p << "\n";
        }
        return kExitOk;
    }

    if (cl.has("plot") || cl.has("scale") || cl.has("axes"))
        throw core::InputError("--plot, --axes and --scale apply to 'ate' only");
    eval::RpeOptions o;
    o.maxDifference = cl.number("max-dt", o.maxDifference);
    o.offset = cl.number("offset", o.offset);
    o.delta = cl.number("delta", o.delta);
    if (const auto u = cl.value("delta-unit"))
        o.unit = eval::parseDeltaUnit(*u);
    const auto r = eval::computeRpe(gt, est, o);
    out << eval::rpeToText(r, o);
    if (const auto j = cl.value("json"))
        writeJson(*j, eval::rpeToJson(r, o));
    return kExitOk;
}
}  // namespace smap::pipeline
