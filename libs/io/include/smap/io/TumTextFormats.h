// Parsers and writers for the TUM RGB-D text formats: image lists (rgb.txt, depth.txt),
// associations.txt and trajectories (timestamp tx ty tz qx qy qz qw).
//
// Lines starting with '#' and blank lines are skipped; ',' and tabs count as spaces (as TUM's
// own scripts do). A malformed line throws core::InputError naming the source and line number.
#pragma once

#include <istream>
#include <string>
#include <vector>

#include "smap/core/Trajectory.h"

namespace smap::io
{
struct TumListEntry
{
    double timestamp = 0.0;
    std::string file;  ///< relative to the list's folder
    size_t line = 0;   ///< 1-based line number in the source
};

struct TumAssociationEntry
{
    double rgbTimestamp = 0.0;
    std::string rgbFile;
    double depthTimestamp = 0.0;
    std::string depthFile;
    size_t line = 0;
};

/// With `badLines`, a malformed line is appended there ("SOURCE:LINE: what") and left out
/// instead of throwing (image lists tolerate a garbage line; trajectories never do).
std::vector<TumListEntry> parseTumList(std::istream& in, const std::string& sourceName,
                                       std::vector<std::string>* badLines = nullptr);
std::vector<TumAssociationEntry> parseTumAssociations(std::istream& in,
                                                      const std::string& sourceName,
                                                      std::vector<std::string>* badLines = nullptr);
core::Trajectory parseTumTrajectory(std::istream& in, const std::string& sourceName);

/// File versions: throw InputError when the file cannot be opened.
std::vector<TumListEntry> readTumList(const std::string& path,
                                      std::vector<std::string>* badLines = nullptr);
std::vector<TumAssociationEntry> readTumAssociations(const std::string& path,
                                                     std::vector<std::string>* badLines = nullptr);
core::Trajectory readTumTrajectory(const std::string& path);

/// The reference trajectories of an input whose own is `groundTruth`: it first, then every
/// "<stem>_*.txt" beside it in name order (7-Scenes' groundtruth_sfm.txt beside groundtruth.txt;
/// a converted rawlog's NAME_groundtruth_sfm.txt beside NAME_groundtruth.txt). Empty for "".
std::vector<std::string> referenceTrajectories(const std::string& groundTruth);

/// One "timestamp tx ty tz qx qy qz qw" line per pose, every number at round-trip precision,
/// quaternion with qw >= 0. Written atomically (temporary file, then rename).
void writeTumTrajectory(const std::string& path, const core::Trajectory& trajectory,
                        const std::string& comment = {});
std::string formatTumPose(const core::StampedPose& pose);
}  // namespace smap::io
