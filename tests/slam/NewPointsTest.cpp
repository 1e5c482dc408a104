// Local mapping starts map points for keypoints beyond close_depth once a covisible keyframe sees
// them where their depth or the two rays say: exact two-view geometry, with decoys that must not
// become points (a second view at the wrong depth, a different descriptor, a movable or unproven
// keypoint).
#include <gtest/gtest.h>

#include <random>

#include "TestData.h"
#include "smap/slam/KeyFrame.h"
#include "smap/slam/LocalMapper.h"
#include "smap/slam/Map.h"
#include "smap/slam/MapPoint.h"
#include "smap/slam/ProjectionSearch.h"

using namespace smap;

namespace
{
constexpr double kBaseline = 0.08;

using Descriptor = std::array<uint8_t, 32>;

/// One keypoint a view sees: where a world point projects, at `depth` (its own depth unless a
/// decoy says otherwise), with `descriptor`.
struct Sighting
{
    Eigen::Vector3d p_world;
    Descriptor descriptor{};
    double depth = 0.0;  ///< 0: the true depth
    float weight = 1.0F;
    bool mappable = true;
};

/// A frame of the sightings seen from T_cam_world: level 0, undistorted, with the grid built.
slam::Frame frameOf(const std::vector<Sighting>& sightings, const Eigen::Isometry3d& T_cam_world)
{
    slam::Frame f;
    f.camera = test::centredCamera(640, 480, 525.0);
    f.bf = kBaseline * f.camera.fx;
    f.closeDepth = 3.0;
    f.features.pyramid = features::ScalePyramid::make(8, 1.2);
    f.features.descriptors = cv::Mat::zeros(static_cast<int>(sightings.size()), 32, CV_8UC1);
    std::vector<int> levels;
    for (size_t i = 0; i < sightings.size(); ++i)
    {
        const Eigen::Vector3d pc = T_cam_world * sightings[i].p_world;
        const auto u = static_cast<float>(f.camera.fx * pc.x() / pc.z() + f.camera.cx);
        const auto v = static_cast<float>(f.camera.fy * pc.y() / pc.z() + f.camera.cy);
        cv::KeyPoint kp(u, v, 31);
        kp.octave = 0;
        f.features.keypoints.push_back(kp);
        f.features.undistorted.push_back(kp.pt);
        const double z = sightings[i].depth > 0.0 ? sightings[i].depth : pc.z();
        f.features.depth.push_back(static_cast<float>(z));
        f.features.rightU.push_back(static_cast<float>(u - f.bf / z));
        std::copy(sightings[i].descriptor.begin(), sightings[i].descriptor.end(),
                  f.features.descriptors.ptr<uint8_t>(static_cast<int>(i)));
        f.weights.push_back(sightings[i].weight);
        f.mappable.push_back(sightings[i].mappable);
        levels.push_back(0);
    }
    f.grid = features::FeatureGrid(f.features.undistorted, levels, 640, 480);
    f.clearMatches();
    f.T_cam_world = T_cam_world;
    return f;
}

Descriptor randomDescriptor(std::mt19937& rng)
{
    Descriptor d{};
    for (auto& b : d)
        b = static_cast<uint8_t>(rng() & 0xFFU);
    return d;
}

/// A wall of `rows` x `cols` points at depth z in front of the origin, spread over the view.
std::vector<Eigen::Vector3d> wall(double z, int rows, int cols)
{
    std::vector<Eigen::Vector3d> out;
    for (int r = 0; r < rows; ++r)
        for (int c = 0; c < cols; ++c)
            out.emplace_back(z * (-0.35 + 0.7 * c / (cols - 1)), z * (-0.25 + 0.5 * r / (rows - 1)),
                             z);
    return out;
}

enum class Decoy
{
    None,
    WrongDepth,      ///< the second view's depth is 4 m, not 6 m
    OtherLook,       ///< the second view's descriptor differs by 96 bits
    Movable,         ///< weight 0 in the first view (a person)
    NotShownStatic,  ///< not mappable in the second view (flow unmeasured)
};

struct Scene
{
    slam::Map map;
    std::shared_ptr<slam::KeyFrame> first, second;
    std::vector<Decoy> farDecoys;  ///< per far point, indices after the close anchors
    size_t anchors = 0;
};

/// Two keyframes 0.3 m apart that share 24 close map points (so that they are covisible) and
/// see 40 points on a wall 6 m away, 16 of them decoys; both views read the far depths times
/// `farDepthScale`.
void buildScene(Scene& s, double farDepthScale = 1.0)
{
    std::mt19937 rng(7);
    const auto close = wall(2.0, 4, 6);
    const auto far = wall(6.0, 5, 8);
    std::vector<Sighting> a, b;
    for (const auto& p : close)
    {
        const auto d = randomDescriptor(rng);
        a.push_back({p, d});
        b.push_back({p, d});
    }
    s.anchors = close.size();
    const Decoy cycle[] = {Decoy::None, Decoy::WrongDepth, Decoy::None, Decoy::OtherLook,
                           Decoy::None, Decoy::Movable,    Decoy::None, Decoy::NotShownStatic,
                           Decoy::None, Decoy::None};
    for (size_t k = 0; k < far.size(); ++k)
    {
        const Decoy decoy = cycle[k % 10];
        const auto d = randomDescriptor(rng);
        Sighting inA{far[k], d}, inB{far[k], d};
        inA.depth = far[k].z() * farDepthScale;
        inB.depth = (far[k] - Eigen::Vector3d(0.3, 0.0, 0.0)).z() * farDepthScale;
        inB.descriptor[0] ^= 0x0FU;  // 4 bits: the same point seen again
        if (decoy == Decoy::WrongDepth)
            inB.depth = 4.0;
        if (decoy == Decoy::OtherLook)
            for (size_t byte = 0; byte < 12; ++byte)
                inB.descriptor[byte] = static_cast<uint8_t>(~inB.descriptor[byte]);
        if (decoy == Decoy::Movable)
            inA.weight = 0.0F;
        if (decoy == Decoy::NotShownStatic)
            inB.mappable = false;
        a.push_back(inA);
        b.push_back(inB);
        s.farDecoys.push_back(decoy);
    }
    Eigen::Isometry3d T_b = Eigen::Isometry3d::Identity();
    T_b.translation() = Eigen::Vector3d(-0.3, 0.0, 0.0);  // camera at x = +0.3
    s.first = s.map.createKeyFrame(frameOf(a, Eigen::Isometry3d::Identity()));
    s.second = s.map.createKeyFrame(frameOf(b, T_b));
    for (size_t i = 0; i < s.anchors; ++i)
    {
        auto mp = s.map.createPoint(close[i], s.first.get());
        mp->addObservation(s.first.get(), i);
        mp->addObservation(s.second.get(), i);
        s.first->points[i] = mp;
        s.second->points[i] = mp;
    }
}

void runLocalMapping(Scene& s, int neighbours)
{
    slam::LocalMappingParameters p;
    p.new_point_neighbours = neighbours;
    p.global_ba_iterations = 0;
    p.ba_iterations = 0;  // the points as made, not as bundle adjustment then moves them
    p.ba_refine_iterations = 0;
    slam::LocalMapper mapper(s.map, p);
    mapper.insertKeyFrame(s.first);
    mapper.insertKeyFrame(s.second);
    mapper.waitUntilIdle();
}
}  // namespace

TEST(NewPoints, FarKeypointsSeenByBothKeyFramesBecomePointsWhereTheyAre)
{
    Scene s;
    buildScene(s);
    const auto truth = wall(6.0, 5, 8);
    runLocalMapping(s, 10);
    int made = 0, decoysMade = 0;
    for (size_t k = 0; k < s.farDecoys.size(); ++k)
    {
        const size_t i = s.anchors + k;
        const auto& inFirst = s.first->points[i];
        const auto& inSecond = s.second->points[i];
        const bool shared = inFirst && inFirst == inSecond && !inFirst->isBad();
        if (s.farDecoys[k] != Decoy::None)
        {
            decoysMade += (inFirst || inSecond) ? 1 : 0;
            continue;
        }
        ASSERT_TRUE(shared) << "far point " << k;
        EXPECT_EQ(inFirst->numObservations(), 2U);
        EXPECT_LT((inFirst->position_world - truth[k]).norm(), 0.02) << "far point " << k;
        made++;
    }
    EXPECT_EQ(made, 24);
    EXPECT_EQ(decoysMade, 0);
    EXPECT_EQ(s.map.points().size(), s.anchors + 24U);
}

TEST(NewPoints, TwoRaysPlaceAFarPointThatBothDepthsPutTooFar)
{
    // Both views read 5 % too deep (30 cm at 6 m): the rays, 2.9 deg apart, see the wall more
    // sharply than the 8 cm virtual baseline's 0.8 deg, so the points go where the rays cross.
    Scene s;
    buildScene(s, 1.05);
    const auto truth = wall(6.0, 5, 8);
    runLocalMapping(s, 10);
    int made = 0;
    for (size_t k = 0; k < s.farDecoys.size(); ++k)
    {
        const auto& mp = s.first->points[s.anchors + k];
        if (s.farDecoys[k] != Decoy::None || !mp)
            continue;
        EXPECT_LT((mp->position_world - truth[k]).norm(), 0.02) << "far point " << k;
        made++;
    }
    EXPECT_EQ(made, 24);
}

TEST(NewPoints, NoNeighboursSearchedMakesNoPoints)
{
    Scene s;
    buildScene(s);
    runLocalMapping(s, 0);
    for (size_t k = 0; k < s.farDecoys.size(); ++k)
        EXPECT_FALSE(s.first->points[s.anchors + k]) << "far point " << k;
    EXPECT_EQ(s.map.points().size(), s.anchors);
}

TEST(NewPoints, MatchFreeKeypointSkipsKeypointsThatHaveAPoint)
{
    Scene s;
    buildScene(s);
    const auto truth = wall(6.0, 5, 8);
    const size_t i = s.anchors;  // far point 0, no decoy
    const uint8_t* d = s.first->features.descriptor(i);
    EXPECT_EQ(slam::matchFreeKeypoint(*s.second, truth[0], 0, d, 3.0, 0.8), static_cast<int>(i));
    s.second->points[i] = s.map.createPoint(truth[0], s.second.get());
    EXPECT_EQ(slam::matchFreeKeypoint(*s.second, truth[0], 0, d, 3.0, 0.8), -1);
}
