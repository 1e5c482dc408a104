// stream_observations: the loop of a robot program that maps while it moves. It reads an MRPT
// rawlog entry by entry, as MRPT's own apps do (CFileGZInputStream + archive), hands every RGB-D
// observation (CObservation3DRangeScan) to the mapper, prints the camera pose of each frame and
// saves the maps at the end. On a robot, the observations come from a live sensor
// (mrpt::hwdrivers::CGenericSensor::getObservations) instead of a file; the rest is the same.
//
// Usage: stream_observations RAWLOG OUT_DIR [CONFIG.ini ...]
//   CONFIG.ini: semantic-mapper configuration files (e.g. the installed
//   share/semantic-mapper/config/synthetic.ini), applied in order over the defaults.
#include <mrpt/config/CConfigFile.h>
#include <mrpt/io/CFileGZInputStream.h>
#include <mrpt/obs/CObservation3DRangeScan.h>
#include <mrpt/obs/CSensoryFrame.h>
#include <mrpt/serialization/CArchive.h>

#include <cstdio>
#include <exception>
#include <filesystem>
#include <string>
#include <vector>

#include "smap/core/InputError.h"
#include "smap/io/RgbdObservationConverter.h"
#include "smap/pipeline/MapOutputWriter.h"
#include "smap/pipeline/SemanticMapper.h"

namespace
{
/// The observations of one rawlog entry: a sensory frame's, or the entry itself.
std::vector<mrpt::obs::CObservation::Ptr> observationsOf(
    const mrpt::serialization::CSerializable::Ptr& entry)
{
    if (auto sf = std::dynamic_pointer_cast<mrpt::obs::CSensoryFrame>(entry))
        return {sf->begin(), sf->end()};
    if (auto obs = std::dynamic_pointer_cast<mrpt::obs::CObservation>(entry))
        return {obs};
    return {};  // actions, odometry-only entries ...
}

smap::pipeline::SemanticMapperParameters parametersFrom(const std::vector<std::string>& files)
{
    smap::pipeline::SemanticMapperParameters params;  // the defaults: the best mode
    for (const auto& file : files)
    {
        if (!std::filesystem::is_regular_file(file))
            throw smap::core::InputError("cannot read configuration '" + file + "'");
        const mrpt::config::CConfigFile cfg(file);
        for (auto* part : params.parts())
            part->loadFromConfigFile(cfg, "");
    }
    return params;
}

/// Tracks one observation; prints its pose, or why it has none.
void track(smap::pipeline::SemanticMapper& mapper, smap::io::RgbdObservationConverter& converter,
           const mrpt::obs::CObservation3DRangeScan& scan, size_t entry, size_t& frames)
{
    const std::string where = "entry " + std::to_string(entry);
    smap::core::RgbdFrame frame;
    try
    {
        frame = converter.convert(scan, where);
    }
    catch (const smap::core::InputError& e)  // one bad observation does not stop the robot
    {
        std::printf("%s: skipped (%s)\n", where.c_str(), e.what());
        return;
    }
    frame.index = frames++;
    const auto r = mapper.process(frame);
    if (!smap::slam::hasPose(r.tracking.status))
    {
        std::printf("frame %zu: %s\n", frame.index,
                    smap::slam::toString(r.tracking.status).c_str());
        return;
    }
    const auto& t = r.tracking.T_world_cam.translation();
    std::printf("frame %zu: %s  x %.3f  y %.3f  z %.3f%s\n", frame.index,
                smap::slam::toString(r.tracking.status).c_str(), t.x(), t.y(), t.z(),
                r.tracking.newKeyFrame ? "  (keyframe)" : "");
}

int run(const std::string& rawlog, const std::string& outDir,
        const std::vector<std::string>& configs)
{
    const auto params = parametersFrom(configs);
    smap::pipeline::SemanticMapper mapper(params);
    smap::io::RgbdObservationConverter converter({},
                                                 rawlog.substr(0, rawlog.rfind('.')) + "_Images");
    mrpt::io::CFileGZInputStream in;
    if (!in.open(rawlog))
        throw smap::core::InputError("cannot open rawlog '" + rawlog + "'");
    auto archive = mrpt::serialization::archiveFrom(in);
    size_t entries = 0, frames = 0;
    for (;;)
    {
        mrpt::serialization::CSerializable::Ptr entry;
        try
        {
            entry = archive.ReadObject();
        }
        catch (const mrpt::serialization::CExceptionEOF&)
        {
            break;  // the end of the recording
        }
        ++entries;
        for (const auto& obs : observationsOf(entry))
            if (auto scan = std::dynamic_pointer_cast<mrpt::obs::CObservation3DRangeScan>(obs))
                track(mapper, converter, *scan, entries, frames);
    }
    mapper.finish();  // local mapping and the segmentation worker drain; maps re-anchored
    std::filesystem::create_directories(outDir);
    const smap::pipeline::MapOutputWriter writer(outDir, {});
    mapper.withMaps(
        [&](smap::mapping::SemanticMapBuilder& maps)
        {
            for (const auto& f : writer.writeMaps(maps))
                std::printf("wrote %s/%s\n", outDir.c_str(), f.c_str());
            std::printf("wrote %s/%s\n", outDir.c_str(),
                        writer.writeScene(maps, mapper.trajectory()).c_str());
        });
    std::printf("%zu rawlog entries, %zu RGB-D frames, %zu keyframes mapped\n", entries, frames,
                static_cast<size_t>(mapper.keyframesSubmitted()));
    return frames > 0 ? 0 : 2;
}
}  // namespace

int main(int argc, char** argv)
{
    if (argc < 3)
    {
        std::fprintf(stderr, "Usage: %s RAWLOG OUT_DIR [CONFIG.ini ...]\n", argv[0]);
        return 2;
    }
    try
    {
        return run(argv[1], argv[2], {argv + 3, argv + argc});
    }
    catch (const smap::core::InputError& e)
    {
        std::fprintf(stderr, "stream_observations: %s\n", e.what());
        return 2;
    }
    catch (const std::exception& e)
    {
        std::fprintf(stderr, "stream_observations: internal error: %s\n", e.what());
        return 1;
    }
}
