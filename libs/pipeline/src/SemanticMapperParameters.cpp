#include "smap/pipeline/SemanticMapperParameters.h"

#include <algorithm>

namespace smap::pipeline
{
void SemanticMapperParameters::applyReproducibleMode()
{
    if (!pipeline.reproducible)
        return;
    localMapping.threaded = false;
    loopClosing.threaded = false;
    if (semanticEvidence.mask_latency_s == 0.0)
        semanticEvidence.mask_latency_s =
            std::min(kReproducibleMaskLatency_s, semanticEvidence.max_mask_age_s);
    pipeline.when_full = WhenFull::Wait;
}
}  // namespace smap::pipeline
