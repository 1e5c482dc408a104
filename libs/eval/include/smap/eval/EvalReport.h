// JSON and text renderings of evaluation results (smap-eval, metrics.json).
#pragma once

#include <string>

#include "smap/core/JsonWriter.h"
#include "smap/eval/AbsoluteTrajectoryError.h"
#include "smap/eval/RelativePoseError.h"

namespace smap::eval
{
/// Keys: rmse, mean, median, std, min, max, pairs, coverage (metres, fraction), plus
/// ground_truth_poses, estimated_poses, max_difference, offset, alignment ("SE3"/"Sim3"), scale.
core::JsonValue ateToJson(const AteResult& r, const AteOptions& o);
/// Keys: translation {rmse, mean, median, std, min, max} (m), rotation {...} (deg), pairs,
/// associated, delta, delta_unit.
core::JsonValue rpeToJson(const RpeResult& r, const RpeOptions& o);
std::string ateToText(const AteResult& r);
std::string rpeToText(const RpeResult& r, const RpeOptions& o);
}  // namespace smap::eval
