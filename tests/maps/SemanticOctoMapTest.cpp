// CSemanticOctoMap: occupancy from rays with free-space carving, the Bayesian class update
// against hand-computed posteriors, .ot/.bt files, serialization, CMultiMetricMap.
#include <gtest/gtest.h>
#include <mrpt/config/CConfigFileMemory.h>
#include <mrpt/io/CMemoryStream.h>
#include <mrpt/maps/CMultiMetricMap.h>
#include <mrpt/serialization/CArchive.h>
#include <octomap/OcTree.h>

#include <cmath>
#include <cstring>
#include <fstream>
#include <opencv2/core.hpp>

#include "TestData.h"
#include "smap/maps/CObservationSemanticRGBD.h"
#include "smap/maps/CSemanticOctoMap.h"
#include "smap/maps/CSemanticPointsMap.h"

using namespace smap;
using maps::CObservationSemanticRGBD;
using maps::CSemanticOctoMap;

namespace
{
/// A camera at the origin looking along +Z at a plane `z` m away, one class, one confidence;
/// f = 40 px, so at 2 m pixels are 5 cm apart (10 cm at the default stride 2).
CObservationSemanticRGBD::Ptr plane(float z, int label, float confidence)
{
    auto o = CObservationSemanticRGBD::Create();
    o->camera.width = 40;
    o->camera.height = 30;
    o->camera.fx = o->camera.fy = 40.0;
    o->camera.cx = 19.5;
    o->camera.cy = 14.5;
    o->colour = cv::Mat(30, 40, CV_8UC3, cv::Scalar(200, 100, 50));
    o->depth = cv::Mat(30, 40, CV_32FC1, cv::Scalar(z));
    o->labels = cv::Mat(30, 40, CV_8UC1, cv::Scalar(label));
    o->confidence = cv::Mat(30, 40, CV_32FC1, cv::Scalar(confidence));
    return o;
}

int occupiedNear(const CSemanticOctoMap& map, float z, float tolerance)
{
    int n = 0;
    for (const auto& v : map.occupiedVoxels())
        n += std::abs(v.centre.z() - z) < tolerance;
    return n;
}
}  // namespace

TEST(CSemanticOctoMap, OccupiedSurfaceWithColourAndClass)
{
    CSemanticOctoMap map;
    auto o = plane(2.0f, 9, 0.9f);
    o->dynamicMask = cv::Mat::zeros(30, 40, CV_8UC1);
    o->dynamicMask(cv::Rect(0, 0, 20, 30)).setTo(255);  // left half dynamic: not mapped
    ASSERT_TRUE(map.insertObservation(*o, mrpt::poses::CPose3D()));
    const auto voxels = map.occupiedVoxels();
    ASSERT_GT(voxels.size(), 20u);
    for (const auto& v : voxels)
    {
        EXPECT_NEAR(v.centre.z(), 2.0f, 0.05f);
        EXPECT_GT(v.centre.x(), -0.05f) << "a dynamic pixel was mapped";
        EXPECT_EQ(v.label, 9);
        EXPECT_EQ(v.r, 50);
        EXPECT_EQ(v.b, 200);
        EXPECT_GT(v.occupancy, 0.5f);
    }
    // The space in front of the plane is known free.
    CSemanticOctoMap::Voxel v;
    ASSERT_TRUE(map.voxelAt({0.3f, 0.0f, 1.0f}, v));
    EXPECT_LT(v.occupancy, 0.5f);
}

TEST(CSemanticOctoMap, FreeSpaceCarvingErasesSomeoneWhoLeft)
{
    CSemanticOctoMap map;
    // A person-sized plane at 1 m, then the wall behind it seen three times.
    map.insertObservation(*plane(1.0f, 15, 0.9f), mrpt::poses::CPose3D());
    ASSERT_GT(occupiedNear(map, 1.0f, 0.05f), 10);
    for (int i = 0; i < 3; i++)
        map.insertObservation(*plane(2.0f, 0, 0.9f), mrpt::poses::CPose3D());
    EXPECT_EQ(occupiedNear(map, 1.0f, 0.05f), 0);
    EXPECT_GT(occupiedNear(map, 2.0f, 0.05f), 10);
}

TEST(CSemanticOctoMap, BayesianClassUpdateMatchesHandComputedPosteriors)
{
    CSemanticOctoMap map;
    map.insertionOptions.label_log_floor = -40.0;  // no flooring: exact Bayes
    const auto pose = mrpt::poses::CPose3D();
    // One pixel per voxel (stride 2 at 2 m = 10 cm, voxels 5 cm). Uniform prior over 21
    // classes; a pixel with confidence c gives c to its label and (1 - c) / 20 to the others.
    map.insertObservation(*plane(2.0f, 15, 0.8f), pose);
    const Eigen::Vector3f p(0.025f, -0.025f, 2.0f);  // pixel (20, 14)
    auto lp = map.classLogProbabilities(p);
    ASSERT_EQ(lp.size(), 21u);
    EXPECT_NEAR(std::exp(lp[15]), 0.8, 1e-5);
    map.insertObservation(*plane(2.0f, 15, 0.8f), pose);
    lp = map.classLogProbabilities(p);
    EXPECT_NEAR(std::exp(lp[15]), 0.64 / (0.64 + 20 * 0.0001), 1e-5);
    map.insertObservation(*plane(2.0f, 9, 0.6f), pose);
    lp = map.classLogProbabilities(p);
    const double person = 0.64 * 0.02, chair = 0.0001 * 0.6, other = 0.0001 * 0.02;
    EXPECT_NEAR(std::exp(lp[15]), person / (person + chair + 19 * other), 1e-5);
    EXPECT_NEAR(std::exp(lp[9]), chair / (person + chair + 19 * other), 1e-5);
    // With the default floor (-8) the same evidence leaves more room to change later.
    CSemanticOctoMap floored;
    for (int i = 0; i < 10; i++)
        floored.insertObservation(*plane(2.0f, 15, 0.8f), pose);
    for (int i = 0; i < 3; i++)
        floored.insertObservation(*plane(2.0f, 9, 0.9f), pose);
    CSemanticOctoMap::Voxel v;
    ASSERT_TRUE(floored.voxelAt(p, v));
    EXPECT_EQ(v.label, 9) << "a floored distribution follows new evidence";
}

TEST(CSemanticOctoMap, FilesSerializationAndMultiMetricMap)
{
    CSemanticOctoMap map;
    map.insertObservation(*plane(2.0f, 15, 0.8f),
                          mrpt::poses::CPose3D(0.5, 0.2, 0.1, 0.3, 0.0, 0.0));
    const auto before = map.occupiedVoxels();
    ASSERT_FALSE(before.empty());

    mrpt::io::CMemoryStream buf;
    auto arch = mrpt::serialization::archiveFrom(buf);
    arch << map;
    buf.Seek(0);
    const auto back = std::dynamic_pointer_cast<CSemanticOctoMap>(arch.ReadObject());
    ASSERT_TRUE(back);
    const auto after = back->occupiedVoxels();
    ASSERT_EQ(after.size(), before.size());
    for (size_t i = 0; i < after.size(); i++)
    {
        EXPECT_EQ(after[i].centre, before[i].centre);
        EXPECT_EQ(after[i].label, before[i].label);
        EXPECT_FLOAT_EQ(after[i].probability, before[i].probability);
    }

    test::TempDir dir;
    map.saveMetricMapRepresentationToFile(dir / "map");
    std::ifstream bt(dir / "map.bt");
    std::string header;
    std::getline(bt, header);
    EXPECT_NE(header.find("Octomap OcTree binary file"), std::string::npos) << header;
    // The .bt holds the occupancy: every occupied voxel of the map is occupied in it.
    {
        octomap::OcTree tree(0.1);
        ASSERT_TRUE(tree.readBinary(dir / "map.bt"));
        EXPECT_DOUBLE_EQ(tree.getResolution(), map.insertionOptions.resolution);
        for (const auto& v : before)
        {
            const octomap::OcTreeNode* n = tree.search(v.centre.x(), v.centre.y(), v.centre.z());
            ASSERT_NE(n, nullptr);
            EXPECT_TRUE(tree.isNodeOccupied(n));
        }
    }
    CSemanticOctoMap loaded;
    loaded.loadOt(dir / "map.ot");
    const auto ot = loaded.occupiedVoxels();
    ASSERT_EQ(ot.size(), before.size());
    // Saved coloured by class: person's VOC colour (192, 128, 128).
    EXPECT_EQ(ot[0].r, 192);
    EXPECT_EQ(ot[0].g, 128);
    EXPECT_NE(test::inputErrorOf([&] { loaded.loadOt(dir / "map.bt"); }).find("map.bt"),
              std::string::npos);

    mrpt::config::CConfigFileMemory cfg(
        "[map]\nsemanticOctoMap_count = 1\nsemanticPointsMap_count = 1\n"
        "[map_semanticOctoMap_00_insertOpts]\nresolution = 0.1\n");
    mrpt::maps::TSetOfMetricMapInitializers inits;
    inits.loadFromConfigFile(cfg, "map");
    mrpt::maps::CMultiMetricMap multi(inits);
    ASSERT_EQ(multi.maps.size(), 2u);
    const auto octo = multi.mapByClass<CSemanticOctoMap>();
    ASSERT_TRUE(octo);
    EXPECT_DOUBLE_EQ(octo->insertionOptions.resolution, 0.1);
    EXPECT_TRUE(multi.insertObservation(*plane(2.0f, 15, 0.8f), mrpt::poses::CPose3D()));
    EXPECT_FALSE(octo->isEmpty());
    EXPECT_FALSE(multi.mapByClass<maps::CSemanticPointsMap>()->isEmpty());
}

// A copy is a deep copy with colours: octomap's own ColorOcTree copy constructor re-creates the
// nodes without their colour (and reads past them); the copy's files and voxels must equal the
// original's.
TEST(CSemanticOctoMap, CopyKeepsEveryVoxelColourAndWritesTheSameFiles)
{
    CSemanticOctoMap map;
    auto near = plane(1.5f, 15, 0.9f);
    near->colour(cv::Rect(0, 0, 20, 30)).setTo(cv::Scalar(10, 220, 30));
    map.insertObservation(*near);
    map.insertObservation(*plane(2.5f, 9, 0.8f));
    const CSemanticOctoMap copy = map;
    const auto a = map.occupiedVoxels();
    const auto b = copy.occupiedVoxels();
    ASSERT_EQ(a.size(), b.size());
    ASSERT_GT(a.size(), 50u);
    for (size_t i = 0; i < a.size(); ++i)
    {
        EXPECT_EQ(a[i].centre, b[i].centre);
        EXPECT_EQ(a[i].r, b[i].r);
        EXPECT_EQ(a[i].g, b[i].g);
        EXPECT_EQ(a[i].b, b[i].b);
        EXPECT_EQ(a[i].label, b[i].label);
    }
    test::TempDir dir;
    map.saveOt(dir / "a.ot", true);
    copy.saveOt(dir / "b.ot", true);
    const std::string fa = test::readTextFile(dir / "a.ot");
    EXPECT_FALSE(fa.empty());
    EXPECT_EQ(fa, test::readTextFile(dir / "b.ot"));
    // Serializing the same map twice gives the same bytes.
    mrpt::io::CMemoryStream s1, s2;
    mrpt::serialization::archiveFrom(s1) << map;
    mrpt::serialization::archiveFrom(s2) << copy;
    ASSERT_EQ(s1.getTotalBytesCount(), s2.getTotalBytesCount());
    EXPECT_EQ(0,
              std::memcmp(s1.getRawBufferData(), s2.getRawBufferData(), s1.getTotalBytesCount()));
}
