#include "smap/apps/EvalApp.h"

#include <mrpt/core/format.h>

#include <algorithm>
#include <filesystem>
#include <opencv2/imgcodecs.hpp>
#include <optional>
#include <sstream>
#include <vector>

#include "smap/apps/CommandLine.h"
#include "smap/core/AtomicFile.h"
#include "smap/core/InputError.h"
#include "smap/core/LabelSet.h"
#include "smap/eval/EvalReport.h"
#include "smap/eval/KeypointDetectionScore.h"
#include "smap/eval/SegmentationScore.h"
#include "smap/eval/TrajectoryPlot.h"
#include "smap/io/TumTextFormats.h"

namespace smap::apps
{
namespace
{
void writeJson(const std::string& path, const core::JsonValue& j)
{
    core::AtomicTextFile f(path);
    f.stream() << j.dump();
    f.commit();
}

/// Where the false positives of a keypoint score are, the precision the outline corners alone
/// would leave, and how the decisions split across the outline.
void printFalsePositives(const eval::KeypointDetectionScore& s, std::ostream& out)
{
    const auto& d = s.falsePositivesByDistance;
    const auto& e = s.falsePositivesByEvidence;
    out << mrpt::format(
        "false positives by distance from a mask: <= 1.5 px %zu, 1.5-3 px %zu, "
        "3-10 px %zu, 10-50 px %zu, farther %zu\n",
        d[0], d[1], d[2], d[3], d[4]);
    out << mrpt::format(
        "false positives by evidence: flow %zu, depth %zu, region %zu, "
        "semantic only %zu, other %zu\n",
        e[0], e[1], e[2], e[3], e[4]);
    out << mrpt::format("precision if only those within 3 px of a mask remained: %.4f\n",
                        s.precisionWithin(3.0));
    const auto& on = s.bandOnMask;
    const auto& beside = s.bandBesideMask;
    out << mrpt::format(
        "outline band (within %d px of a mask edge, scored or not): said dynamic %.1f %% of "
        "%zu keypoints on a mask, %.1f %% of %zu beside one\n",
        eval::KeypointDetectionScore::kOutlineBandPx, 100.0 * on.saidFraction(), on.keypoints,
        100.0 * beside.saidFraction(), beside.keypoints);
    out << mrpt::format(
        "outline bound: right on every keypoint off the band and saying dynamic at one rate on "
        "both sides of it, recall %.2f leaves precision %.4f at best (%zu keypoints on a mask "
        "off the band)\n",
        eval::KeypointDetectionScore::kTargetRecall,
        s.bestPrecisionAtRecall(eval::KeypointDetectionScore::kTargetRecall), s.maskOffBand);
}

/// The evidence tables of DEBUG_DIR, each with the ground-truth mask of its stem.
std::vector<std::pair<std::filesystem::path, std::filesystem::path>> keypointTables(
    const std::string& maskDir, const std::string& debugDir)
{
    namespace fs = std::filesystem;
    if (!fs::is_directory(maskDir) || !fs::is_directory(debugDir))
        throw core::InputError(
            mrpt::format("'%s' and '%s' must both be folders", maskDir.c_str(), debugDir.c_str()));
    std::vector<std::pair<fs::path, fs::path>> tables;
    for (const auto& e : fs::directory_iterator(debugDir))
        if (e.path().extension() == ".csv")
            tables.emplace_back(e.path(), fs::path(maskDir) / (e.path().stem().string() + ".png"));
    std::sort(tables.begin(), tables.end());
    if (tables.empty())
        throw core::InputError("'" + debugDir +
                               "' has no keypoint tables (run semantic-mapper --dynamic-debug)");
    for (const auto& [table, mask] : tables)
        if (!fs::exists(mask))
            throw core::InputError(mrpt::format("'%s' has no ground-truth mask '%s'",
                                                table.string().c_str(), mask.string().c_str()));
    return tables;
}

/// Every table scored with `o`; a label image (o.decision not Table) is LABEL_DIR/<stem>.png.
eval::KeypointDetectionScore scoreTables(
    const std::vector<std::pair<std::filesystem::path, std::filesystem::path>>& tables,
    eval::KeypointScoreOptions o, const std::string& labelDir)
{
    eval::KeypointDetectionScore total;
    for (const auto& [table, mask] : tables)
    {
        if (o.decision != eval::KeypointDecision::Table)
        {
            o.labelPng = (std::filesystem::path(labelDir) / (table.stem().string() + ".png"));
            if (!std::filesystem::exists(o.labelPng))
                throw core::InputError(mrpt::format("'%s' has no label image '%s'",
                                                    table.string().c_str(), o.labelPng.c_str()));
        }
        total += eval::scoreKeypointFrame(table.string(), mask.string(), o);
    }
    return total;
}

void printKeypointScore(const eval::KeypointDetectionScore& s, int edgeMargin, std::ostream& out)
{
    out << mrpt::format("frames %zu  recall %.4f  precision %.4f  (tp %zu fp %zu fn %zu tn %zu)",
                        s.frames, s.recall(), s.precision(), s.truePositives, s.falsePositives,
                        s.falseNegatives, s.trueNegatives);
    if (edgeMargin > 0)
        out << mrpt::format("  left out within %d px of a mask edge: %zu", edgeMargin, s.nearEdge);
    out << "\n";
    printFalsePositives(s, out);
}

/// The classes --classes names (ids in the --labels set, default PASCAL VOC), or `defaults`.
std::vector<std::pair<int, std::string>> namedClasses(const CommandLine& cl, const char* defaults)
{
    const core::LabelSet labels = cl.has("labels") ? core::LabelSet::loadCsv(*cl.value("labels"))
                                                   : core::LabelSet::pascalVoc();
    std::vector<std::pair<int, std::string>> classes;
    std::stringstream names(cl.value("classes").value_or(defaults));
    for (std::string n; std::getline(names, n, ',');)
        if (!n.empty())
            classes.emplace_back(labels.idOf(n), n);
    return classes;
}

/// smap-eval keypoints: every DEBUG_DIR/*.csv against MASK_DIR/<same stem>.png, decided by the
/// tables or, with --said-by LABEL_DIR, by the label images there: alone, then within the
/// outline band only.
int scoreKeypoints(const std::string& maskDir, const std::string& debugDir, const CommandLine& cl,
                   std::ostream& out)
{
    eval::KeypointScoreOptions o;
    o.edgeMargin = static_cast<int>(cl.integer("edge-margin", 0));
    if (o.edgeMargin < 0)
        throw core::InputError(mrpt::format("--edge-margin %d must be >= 0", o.edgeMargin));
    const auto tables = keypointTables(maskDir, debugDir);
    const auto json = cl.value("json");
    const auto labelDir = cl.value("said-by");
    if (!labelDir)
    {
        const auto total = scoreTables(tables, o, "");
        printKeypointScore(total, o.edgeMargin, out);
        if (json)
            writeJson(*json, total.toJson());
        return kExitOk;
    }
    if (!std::filesystem::is_directory(*labelDir))
        throw core::InputError("--said-by '" + *labelDir + "' is not a folder");
    for (const auto& [id, name] : namedClasses(cl, "person"))
        o.saidLabels.push_back(id);
    if (o.saidLabels.empty())
        throw core::InputError("--classes names no class");
    o.decision = eval::KeypointDecision::Labels;
    const auto byLabels = scoreTables(tables, o, *labelDir);
    out << "decided by the label images of " << *labelDir << ":\n";
    printKeypointScore(byLabels, o.edgeMargin, out);
    o.decision = eval::KeypointDecision::LabelsInBand;
    const auto inBand = scoreTables(tables, o, *labelDir);
    out << mrpt::format(
        "decided by the tables, and within %d px of a mask edge by the label images:\n",
        eval::KeypointDetectionScore::kOutlineBandPx);
    printKeypointScore(inBand, o.edgeMargin, out);
    if (json)
    {
        auto j = core::JsonValue::object();
        j.set("labels", byLabels.toJson()).set("labels_in_band", inBand.toJson());
        writeJson(*json, j);
    }
    return kExitOk;
}

/// smap-eval segmentation: every PRED_DIR/*.png against GT_DIR/<same name>.
int scoreSegmentation(const std::string& gtDir, const std::string& predDir, const CommandLine& cl,
                      std::ostream& out)
{
    namespace fs = std::filesystem;
    if (!fs::is_directory(gtDir) || !fs::is_directory(predDir))
        throw core::InputError(
            mrpt::format("'%s' and '%s' must both be folders", gtDir.c_str(), predDir.c_str()));
    const auto classes = namedClasses(cl, "person,chair,tvmonitor");
    eval::SegmentationScoreOptions o;
    o.iouThreshold = cl.number("iou-threshold", o.iouThreshold);
    o.minAreaFraction = cl.number("min-area", o.minAreaFraction);
    o.bandRadius = static_cast<int>(cl.integer("band", o.bandRadius));
    if (const auto v = cl.value("void"))
        o.voidLabel = *v == "none" ? -1 : static_cast<int>(cl.integer("void", 255));
    if (!(o.iouThreshold > 0.0 && o.iouThreshold <= 1.0) ||
        !(o.minAreaFraction >= 0.0 && o.minAreaFraction < 1.0) || o.bandRadius < 0 ||
        o.voidLabel > 255)
        throw core::InputError(
            "--iou-threshold must be in (0, 1], --min-area in [0, 1), --band >= 0, --void "
            "0-255 or none");

    std::vector<fs::path> predictions;
    for (const auto& e : fs::directory_iterator(predDir))
        if (e.path().extension() == ".png")
            predictions.push_back(e.path());
    std::sort(predictions.begin(), predictions.end());
    if (predictions.empty())
        throw core::InputError("'" + predDir + "' has no label images (run smap-segment)");
    eval::SegmentationScore score(classes, o);
    for (const auto& p : predictions)
    {
        const fs::path gt = fs::path(gtDir) / p.filename();
        if (!fs::exists(gt))
            throw core::InputError(mrpt::format("'%s' has no ground truth '%s'", p.string().c_str(),
                                                gt.string().c_str()));
        const cv::Mat truth = cv::imread(gt.string(), cv::IMREAD_UNCHANGED);
        const cv::Mat pred = cv::imread(p.string(), cv::IMREAD_UNCHANGED);
        for (const auto& [img, path] : {std::pair{truth, gt}, std::pair{pred, p}})
            if (img.empty() || img.type() != CV_8UC1)
                throw core::InputError("'" + path.string() +
                                       "' is not an 8-bit single-channel label image");
        if (truth.size() != pred.size())
            throw core::InputError(mrpt::format("'%s' is %dx%d but its ground truth '%s' is %dx%d",
                                                p.string().c_str(), pred.cols, pred.rows,
                                                gt.string().c_str(), truth.cols, truth.rows));
        score.addFrame(truth, pred);
    }
    out << score.toText();
    if (const auto j = cl.value("json"))
        writeJson(*j, score.toJson());
    return kExitOk;
}

/// Throws core::InputError for an option the command `verb` does not take.
void checkOptionsApply(const std::string& verb, const CommandLine& cl)
{
    const bool saidBy = verb == "keypoints" && cl.has("said-by");
    if (verb != "segmentation")
    {
        for (const char* o : {"void", "min-area", "iou-threshold", "band"})
            if (cl.has(o))
                throw core::InputError(std::string("--") + o + " applies to 'segmentation' only");
        for (const char* o : {"classes", "labels"})
            if (cl.has(o) && !saidBy)
                throw core::InputError(std::string("--") + o +
                                       " applies to 'segmentation' and 'keypoints --said-by' only");
    }
    for (const char* o : {"edge-margin", "said-by"})
        if (verb != "keypoints" && cl.has(o))
            throw core::InputError(std::string("--") + o + " applies to 'keypoints' only");
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
           "  smap-eval keypoints MASK_DIR DEBUG_DIR [--edge-margin PX] [--json FILE]\n"
           "                       [--said-by LABEL_DIR [--classes a,b] [--labels CSV]]\n"
           "  smap-eval segmentation GT_DIR PRED_DIR [--classes a,b] [--void ID|none]\n"
           "                       [--min-area F] [--iou-threshold T] [--band PX] [--labels CSV]\n"
           "                       [--json FILE]\n"
           "\n"
           "keypoints: dynamic-keypoint recall and precision of semantic-mapper --dynamic-debug\n"
           "  tables (DEBUG_DIR/NNNNNN.csv) against ground-truth masks (MASK_DIR/NNNNNN.png,\n"
           "  e.g. the dynamic/ folder smap-synth writes). --edge-margin PX leaves out the\n"
           "  keypoints within PX of a mask edge (default 0: all scored), whose label is a coin\n"
           "  flip for a corner on an outline. Then where the false positives are: by distance\n"
           "  from the nearest mask pixel and by the evidence that decided them, and the\n"
           "  precision if only the outline corners within 3 px of a mask were false, and the\n"
           "  share said dynamic on either side of the outline (within 3 px). --said-by LABEL_DIR\n"
           "  scores instead what a segmentation would decide (LABEL_DIR/NNNNNN.png, 8-bit class\n"
           "  ids: dynamic where it holds one of --classes, default person), then the tables'\n"
           "  decisions with the outline band's taken from the segmentation.\n"
           "segmentation: the paper's Table III per-class frame scores (TP/FN/FP/TN, FPR, FNR,\n"
           "  Re, Pr, PWC; correctly segmented = IoU >= --iou-threshold, default 0.5), pixel IoU\n"
           "  and IoU within --band px (default 5) of true class edges, for every PRED_DIR/*.png\n"
           "  (smap-segment's output) against GT_DIR/<same name> (e.g. smap-synth's labels/).\n"
           "  --classes (default person,chair,tvmonitor), --void: ground-truth id left out of\n"
           "  scoring (default 255; 'none' scores every pixel), --min-area: fraction of the\n"
           "  pixels a class must cover to count as present or predicted (default 0.001).\n"
           "GT and EST are TUM trajectory files (timestamp tx ty tz qx qy qz qw). Where a data\n"
           "  set has two pseudo ground truths that disagree, score against both: 7-Scenes'\n"
           "  groundtruth_sfm.txt (structure from motion, the colour camera; the primary one)\n"
           "  and groundtruth.txt (KinectFusion, the depth camera), 49 mm apart on redkitchen:\n"
           "    smap-eval ate DATA/groundtruth_sfm.txt OUT/trajectory.txt\n"
           "    smap-eval ate DATA/groundtruth.txt OUT/trajectory.txt\n"
           "  (semantic-mapper reports both in metrics.json by itself; docs/evaluation.md).\n"
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
    cl.option("classes").option("void").option("min-area").option("iou-threshold").option("band");
    cl.option("labels").option("edge-margin").option("said-by");
    cl.parse(args);
    if (cl.has("help"))
    {
        out << usage();
        return kExitOk;
    }
    const auto& pos = cl.positionals();
    if (pos.size() != 3 ||
        (pos[0] != "ate" && pos[0] != "rpe" && pos[0] != "keypoints" && pos[0] != "segmentation"))
        throw core::InputError(
            "expected 'smap-eval ate GT EST', 'smap-eval rpe GT EST', "
            "'smap-eval keypoints MASK_DIR DEBUG_DIR' or 'smap-eval segmentation GT_DIR "
            "PRED_DIR' (see --help)");
    checkOptionsApply(pos[0], cl);
    if (pos[0] == "keypoints")
        return scoreKeypoints(pos[1], pos[2], cl, out);
    if (pos[0] == "segmentation")
        return scoreSegmentation(pos[1], pos[2], cl, out);
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
}  // namespace smap::apps
