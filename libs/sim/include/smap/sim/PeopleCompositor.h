// Composites moving people (RGBA cut-outs) into a real RGB-D sequence with ground-truth poses:
// each person is a flat vertical billboard (SpriteBillboard) standing on the estimated floor and
// facing the camera, walking back and forth in world coordinates, drawn with a per-pixel depth
// test against the real depth and written into the depth image. Gives real textures and real sensor
// noise with exactly known motion.
#pragma once

#include <mrpt/poses/CPose3D.h>

#include <Eigen/Core>
#include <opencv2/core/mat.hpp>
#include <string>
#include <vector>

#include "smap/core/RgbdFrame.h"
#include "smap/core/Trajectory.h"
#include "smap/sim/SpriteBillboard.h"

namespace smap::sim
{
/// How the composited people move (smap-synth --scenario).
enum class CompositeScenario
{
    Random,       ///< each walks back and forth on a random line, spread over the sequence
    Crossing,     ///< walking straight across the view, 1.5 - 3 m away
    Crowd,        ///< fast walkers 0.9 - 1.6 m in front of the same frame: they fill the view
    Seated,       ///< people in place who sway and gesture (a few cm to 15 cm, ~0.4 Hz)
    StopAndStay,  ///< walks in, stands still for 5 s, walks on, stands again
};
/// "random", "crossing", "crowd", "seated", "stop_and_stay"; throws InputError otherwise.
CompositeScenario compositeScenarioFromString(const std::string& name);
std::string toString(CompositeScenario s);
/// The people count a scenario is made for (random and crossing 2, crowd 3, seated 2,
/// stop-and-stay 1).
size_t defaultPeopleCount(CompositeScenario s);

/// Where the composited people are placed (smap-synth --scenario, --distance-scale).
struct CompositeLayout
{
    CompositeScenario scenario = CompositeScenario::Random;
    /// Multiplies how far ahead of its anchor camera each walking line starts (along the
    /// camera's view projected on the floor), so that the same motion covers less of the view
    /// (larger) or more (smaller). In (0, 10].
    double distanceScale = 1.0;

    /// Throws InputError (naming the distance scale) when a value is out of range.
    void validate() const;
};

struct CompositedPerson
{
    cv::Mat sprite;             ///< CV_8UC4 BGRA cut-out
    double height = 1.75;       ///< metres
    Eigen::Vector3d start;      ///< feet position on the floor at t = 0 (world)
    Eigen::Vector3d direction;  ///< unit, horizontal walking direction
    double halfRange = 1.0;     ///< walks between start +- halfRange along direction
    double speed = 1.0;         ///< m/s
    double phase = 0.0;         ///< s
    /// Seconds standing still at each end of the walk (0: turns at once).
    double dwell = 0.0;
    /// Sways in place instead: start + halfRange x sin(2 pi (t + phase) / swayPeriod) along
    /// direction.
    bool sway = false;
    double swayPeriod = 2.5;  ///< s
    uint16_t instanceId = 1;

    Eigen::Vector3d feetAt(double t) const;
};

struct CompositeFrame
{
    cv::Mat colour;     ///< CV_8UC3
    cv::Mat depth;      ///< CV_32FC1 metres (person depth where a person is in front)
    cv::Mat labels;     ///< CV_8UC1: 15 on people, 255 (unknown) elsewhere
    cv::Mat instances;  ///< CV_16UC1: person instance ids, 0 elsewhere
    cv::Mat dynamic;    ///< CV_8UC1: 255 on people (they always move), else 0
    std::vector<std::pair<std::string, mrpt::poses::CPose3D>> objectPoses;
};

struct FreeSpaceCheck
{
    size_t samples = 0;  ///< body samples tested
    size_t inside = 0;   ///< within 20 cm of a surface some probe sees
    size_t unseen = 0;   ///< not inside, but seen free by no probe
};

class PeopleCompositor
{
public:
    static constexpr uint8_t kUnknownLabel = 255;

    /// A frame of the real sequence with its ground-truth pose, used to see the geometry.
    struct Probe
    {
        core::RgbdFrame frame;
        mrpt::poses::CPose3D T_world_cam;
    };

    /// Finds the floor: a RANSAC plane among the lowest 30% of the points the probes see (along
    /// the cameras' mean image-up), within 35 degrees of horizontal; its normal is "up". Then
    /// places `count` people, person i 1.2 - 3.5 m in front of probe i * probes / count (so
    /// that they are spread over the sequence), walking back and forth (0.5 - 1 m each way,
    /// mostly across that view): among random candidates it keeps the walking line with the
    /// fewest body samples not known to be free space (inside a surface a probe sees, or seen
    /// free by no probe). Sprites are BGRA.
    PeopleCompositor(const std::vector<cv::Mat>& sprites, const core::Trajectory& T_world_cam,
                     const std::vector<Probe>& probes, size_t count, uint32_t seed,
                     const CompositeLayout& layout = {});

    CompositeFrame composite(const core::RgbdFrame& frame, const mrpt::poses::CPose3D& T_world_cam,
                             double t) const;

    const std::vector<CompositedPerson>& people() const { return people_; }
    const Eigen::Vector3d& up() const { return up_; }
    double floorHeight() const { return floorHeight_; }  ///< along up()
    /// Body samples of the chosen walking lines not known to be free space (0 = every sample
    /// was seen free by a probe and lies in no observed surface).
    size_t freeSpaceViolations() const { return freeSpace_.inside + freeSpace_.unseen; }
    /// The same, split: samples within 20 cm of a surface a probe sees (a likely collision)
    /// and samples that no probe sees free (unknown space), out of all body samples.
    const FreeSpaceCheck& freeSpaceCheck() const { return freeSpace_; }

private:
    std::vector<CompositedPerson> people_;
    std::vector<SpriteBillboard> billboards_;  ///< of people_, in order
    Eigen::Vector3d up_;
    double floorHeight_ = 0.0;
    FreeSpaceCheck freeSpace_;
};
}  // namespace smap::sim
