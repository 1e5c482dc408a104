#include "smap/dynamic/SemanticEvidenceParameters.h"

#include <mrpt/core/format.h>

#include "smap/core/InputError.h"

namespace smap::dynamic
{
core::OptionFields SemanticEvidenceParameters::fields(const std::string& section)
{
    core::OptionFields f(section, "semantic_evidence");
    f.add("enabled", enabled)
        .add("movable_prior", movable_prior)
        .add("mask_latency_s", mask_latency_s)
        .add("max_mask_age_s", max_mask_age_s)
        .add("dilation_px", dilation_px)
        .add("age_dilation_px_per_s", age_dilation_px_per_s)
        .add("max_dilation_px", max_dilation_px)
        .add("depth_margin", depth_margin)
        .add("sample_step", sample_step)
        .add("still_dilation_px", still_dilation_px)
        .add("still_part_max_moving", still_part_max_moving);
    return f;
}

void SemanticEvidenceParameters::loadFromConfigFile(const mrpt::config::CConfigFileBase& cfg,
                                                    const std::string& section)
{
    fields(section).load(cfg);
    if (!(movable_prior >= 0.0))
        throw core::InputError(
            mrpt::format("[semantic_evidence] movable_prior = %g must be >= 0 (above 1: no class)",
                         movable_prior));
    if (!(mask_latency_s >= 0.0) || !(max_mask_age_s > 0.0) || mask_latency_s > max_mask_age_s ||
        max_mask_age_s > 60.0)
        throw core::InputError(mrpt::format(
            "[semantic_evidence] mask_latency_s = %g must be in [0, max_mask_age_s = %g] and "
            "max_mask_age_s in (0, 60] s",
            mask_latency_s, max_mask_age_s));
    if (!(dilation_px >= 0.0) || !(age_dilation_px_per_s >= 0.0) ||
        !(max_dilation_px >= dilation_px) || max_dilation_px > 200.0)
        throw core::InputError(mrpt::format(
            "[semantic_evidence] need 0 <= dilation_px = %g <= max_dilation_px = %g <= 200 and "
            "age_dilation_px_per_s = %g >= 0",
            dilation_px, max_dilation_px, age_dilation_px_per_s));
    if (!(depth_margin >= 0.0))
        throw core::InputError(
            mrpt::format("[semantic_evidence] depth_margin = %g must be >= 0", depth_margin));
    if (sample_step < 1 || sample_step > 32)
        throw core::InputError(
            mrpt::format("[semantic_evidence] sample_step = %d must be in [1, 32]", sample_step));
    if (!(still_dilation_px <= 200.0))
        throw core::InputError(mrpt::format(
            "[semantic_evidence] still_dilation_px = %g must be <= 200 (negative: off)",
            still_dilation_px));
    if (!(still_part_max_moving >= 0.0 && still_part_max_moving <= 1.0))
        throw core::InputError(
            mrpt::format("[semantic_evidence] still_part_max_moving = %g must be in [0, 1]",
                         still_part_max_moving));
}

void SemanticEvidenceParameters::saveToConfigFile(mrpt::config::CConfigFileBase& cfg,
                                                  const std::string& section) const
{
    // Saving only reads the fields the list points at.
    const_cast<SemanticEvidenceParameters*>(this)->fields(section).save(cfg);
}
}  // namespace smap::dynamic
