// Feature-rich textures made procedurally (nothing downloaded), deterministic for a seed, so
// that ORB finds corners on every rendered surface.
#pragma once

#include <cstdint>
#include <opencv2/core/mat.hpp>

namespace smap::sim
{
enum class TextureKind
{
    Noise,   ///< multi-octave coloured value noise (plaster, stone)
    Tiles,   ///< tiles with grout lines and per-tile tint
    Wood,    ///< wood grain rings
    Poster,  ///< random shapes and stroke "text" on paper
    Fabric,  ///< woven stripes and checks (sofa)
    Carpet,  ///< speckled short-pile carpet
    Paint,   ///< painted plaster: one light colour, faint blotches and a few scuffs
};

/// A `size` x `size` CV_8UC3 (BGR) texture. Same (kind, size, seed) gives the same pixels.
cv::Mat makeTexture(TextureKind kind, int size, uint32_t seed);
}  // namespace smap::sim
