#include "smap/eval/EvalReport.h"

#include <mrpt/core/format.h>

#include <string>

namespace smap::eval
{
namespace
{
void addStats(core::JsonValue& j, const ErrorStatistics& s)
{
    j.set("rmse", s.rmse).set("mean", s.mean).set("median", s.median).set("std", s.std);
    j.set("min", s.min).set("max", s.max);
}
}  // namespace

core::JsonValue ateToJson(const AteResult& r, const AteOptions& o)
{
    auto j = core::JsonValue::object();
    addStats(j, r.translation);
    j.set("pairs", static_cast<uint64_t>(r.pairs)).set("coverage", r.coverage);
    j.set("ground_truth_poses", static_cast<uint64_t>(r.groundTruthPoses));
    j.set("estimated_poses", static_cast<uint64_t>(r.estimatedPoses));
    auto gap = core::JsonValue::object();
    gap.set("poses", static_cast<uint64_t>(r.longestGap.poses));
    if (r.longestGap.poses > 0)
    {
        gap.set("first_row", static_cast<uint64_t>(r.longestGap.firstRow));
        gap.set("first_timestamp", r.longestGap.firstTimestamp);
        gap.set("last_timestamp", r.longestGap.lastTimestamp);
    }
    j.set("longest_gap", gap);
    j.set("max_difference", o.maxDifference).set("offset", o.offset);
    j.set("alignment", o.withScale ? "Sim3" : "SE3").set("scale", r.alignment.scale);
    j.set("units", "m");
    return j;
}

core::JsonValue rpeToJson(const RpeResult& r, const RpeOptions& o)
{
    auto t = core::JsonValue::object();
    addStats(t, r.translation);
    auto rot = core::JsonValue::object();
    addStats(rot, r.rotation);
    auto j = core::JsonValue::object();
    j.set("translation", t).set("rotation", rot);
    j.set("translation_units", "m").set("rotation_units", "deg");
    j.set("pairs", static_cast<uint64_t>(r.pairs))
        .set("associated", static_cast<uint64_t>(r.associated));
    j.set("delta", o.delta).set("delta_unit", toString(o.unit));
    return j;
}

std::string ateToText(const AteResult& r)
{
    const auto& s = r.translation;
    const AteGap& g = r.longestGap;
    const std::string gap =
        g.poses == 0
            ? std::string()
            : mrpt::format(
                  "  longest gap %zu ground-truth poses without an estimate (rows "
                  "%zu-%zu, t %.6f to %.6f)\n",
                  g.poses, g.firstRow, g.firstRow + g.poses - 1, g.firstTimestamp, g.lastTimestamp);
    return mrpt::format(
        "ATE (translation, m)\n  rmse    %.6f\n  mean    %.6f\n  median  %.6f\n  std     %.6f\n"
        "  min     %.6f\n  max     %.6f\n  pairs   %zu of %zu ground-truth poses (coverage "
        "%.1f%%)\n"
        "%s"
        "  scale   %.6f\n",
        s.rmse, s.mean, s.median, s.std, s.min, s.max, r.pairs, r.groundTruthPoses,
        100.0 * r.coverage, gap.c_str(), r.alignment.scale);
}

std::string rpeToText(const RpeResult& r, const RpeOptions& o)
{
    return mrpt::format(
        "RPE over %g %s (%zu intervals)\n  translation rmse %.6f m, mean %.6f, median %.6f, max "
        "%.6f\n"
        "  rotation    rmse %.6f deg, mean %.6f, median %.6f, max %.6f\n",
        o.delta, toString(o.unit).c_str(), r.pairs, r.translation.rmse, r.translation.mean,
        r.translation.median, r.translation.max, r.rotation.rmse, r.rotation.mean,
        r.rotation.median, r.rotation.max);
}
}  // namespace smap::eval
