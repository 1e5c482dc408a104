// Every part of semantic-mapper's configuration, each loaded once from the same configuration.
#pragma once

#include <mrpt/config/CLoadableOptions.h>

#include <vector>

#include "smap/dynamic/DynamicParameters.h"
#include "smap/dynamic/SemanticEvidenceParameters.h"
#include "smap/features/OrbParameters.h"
#include "smap/mapping/DynamicRegionFinder.h"
#include "smap/mapping/MapBuilderParameters.h"
#include "smap/pipeline/PipelineParameters.h"
#include "smap/segmentation/SegmentationParameters.h"
#include "smap/slam/SlamParameters.h"

namespace smap::pipeline
{
struct SemanticMapperParameters
{
    features::OrbParameters orb;
    slam::TrackerParameters tracking;
    slam::LocalMappingParameters localMapping;
    slam::LoopClosingParameters loopClosing;
    dynamic::DynamicParameters dynamic;
    dynamic::SemanticEvidenceParameters semanticEvidence;
    segmentation::SegmentationParameters segmentation;
    mapping::DynamicRegionParameters association;
    mapping::MapBuilderParameters map;
    PipelineParameters pipeline;

    /// [pipeline] reproducible = true: the keys whose effect depends on the threads' timing
    /// take their deterministic values (local mapping and loop closing on the tracking thread,
    /// [semantic_evidence] mask_latency_s = kReproducibleMaskLatency_s unless set, keyframe
    /// queue full: wait). Nothing changes when it is false. Idempotent.
    void applyReproducibleMode();
    /// s: the mask latency of reproducible runs (3 frames at 30 frames/s): the segmentation
    /// of a keyframe usually ends within it, so that tracking seldom waits.
    static constexpr double kReproducibleMaskLatency_s = 0.1;

    /// The parts, in the order the configuration reference lists them.
    std::vector<mrpt::config::CLoadableOptions*> parts()
    {
        return {&orb,     &tracking,         &localMapping, &loopClosing,
                &dynamic, &semanticEvidence, &segmentation, &association,
                &map,     &pipeline};
    }
    std::vector<const mrpt::config::CLoadableOptions*> parts() const
    {
        return {&orb,     &tracking,         &localMapping, &loopClosing,
                &dynamic, &semanticEvidence, &segmentation, &association,
                &map,     &pipeline};
    }
};
}  // namespace smap::pipeline
