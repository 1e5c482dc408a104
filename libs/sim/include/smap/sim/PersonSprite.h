// The person cut-outs people are drawn from (data/people/): RGBA sprites of real people, each
// standing or sitting, with the range of real heights it may be drawn at.
#pragma once

#include <opencv2/core/mat.hpp>
#include <string>
#include <vector>

namespace smap::sim
{
struct PersonSprite
{
    enum class Posture
    {
        Standing,
        Sitting
    };
    std::string file;  ///< path it was read from
    cv::Mat image;     ///< CV_8UC4 BGRA; alpha >= 128 is the person
    Posture posture = Posture::Standing;
    double minHeight = 1.6;   ///< metres, floor to the top of the head
    double maxHeight = 1.85;  ///< metres
};

/// The sprites of `folder`: the ones people.csv lists (file,kind,min_height_m,max_height_m per
/// line, kind standing or sitting), else every person_*.png as standing, 1.6 - 1.85 m; in file
/// name order. Throws core::InputError naming the folder, or the list's file and line, when a
/// sprite cannot be read or is not RGBA, or when there is none.
std::vector<PersonSprite> loadPersonSprites(const std::string& folder);
}  // namespace smap::sim
