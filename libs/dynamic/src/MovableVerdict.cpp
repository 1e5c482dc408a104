#include "smap/dynamic/MovableVerdict.h"

namespace smap::dynamic
{
std::vector<bool> movableVerdicts(const MovableEvidence& e)
{
    using Label = MovableLabelTracker::Label;
    using Motion = MovableLabelTracker::Motion;
    const size_t n = e.pixels.size();
    std::vector<bool> movable(n, false);
    for (size_t i = 0; i < n; ++i)
    {
        const float z = i < e.depth.size() ? e.depth[i] : 0.0F;
        const Label label = i < e.labels.size() ? e.labels[i] : Label::Unknown;
        const bool still = i < e.motion.size() && e.motion[i] == Motion::Still;
        const cv::Point2f& p = e.pixels[i];
        if (label == Label::Unknown)
            movable[i] = e.grown.contains(p.x, p.y, z, e.depthMargin);
        else if (label == Label::Static && still)
            movable[i] = e.still.contains(p.x, p.y, z, e.depthMargin);
        else
            movable[i] = label == Label::Movable;
    }
    return movable;
}
}  // namespace smap::dynamic
