// CObservationSemanticRGBD and CSemanticPointsMap as MRPT classes: insertion with known
// geometry and label fusion, serialization round trips (also through a rawlog by class name),
// PLY round trip, CMultiMetricMap declared from INI text, visualization.
#include <gtest/gtest.h>
#include <mrpt/config/CConfigFileMemory.h>
#include <mrpt/io/CFileGZInputStream.h>
#include <mrpt/io/CFileGZOutputStream.h>
#include <mrpt/io/CMemoryStream.h>
#include <mrpt/maps/CMultiMetricMap.h>
#include <mrpt/obs/CObservationOdometry.h>
#include <mrpt/opengl/CPointCloudColoured.h>
#include <mrpt/opengl/CSetOfObjects.h>
#include <mrpt/serialization/CArchive.h>

#include <opencv2/core.hpp>

#include "TestData.h"
#include "smap/maps/CObservationSemanticRGBD.h"
#include "smap/maps/CSemanticPointsMap.h"

using namespace smap;
using maps::CObservationSemanticRGBD;
using maps::CSemanticPointsMap;

namespace
{
/// A camera looking at a wall 2 m ahead: left half person (15, p 0.8), right half chair (9,
/// p 0.6); the central 10 columns dynamic.
CObservationSemanticRGBD::Ptr wallObservation()
{
    auto o = CObservationSemanticRGBD::Create();
    o->sensorLabel = "keyframe";
    o->timestamp = mrpt::Clock::fromDouble(1.0e9);
    o->camera.width = 40;
    o->camera.height = 30;
    o->camera.fx = o->camera.fy = 40.0;
    o->camera.cx = 19.5;
    o->camera.cy = 14.5;
    o->colour = cv::Mat(30, 40, CV_8UC3, cv::Scalar(10, 20, 30));
    o->depth = cv::Mat(30, 40, CV_32FC1, cv::Scalar(2.0f));
    o->labels = cv::Mat(30, 40, CV_8UC1, cv::Scalar(15));
    o->labels(cv::Rect(20, 0, 20, 30)).setTo(9);
    o->confidence = cv::Mat(30, 40, CV_32FC1, cv::Scalar(0.8f));
    o->confidence(cv::Rect(20, 0, 20, 30)).setTo(0.6f);
    o->dynamicMask = cv::Mat::zeros(30, 40, CV_8UC1);
    o->dynamicMask(cv::Rect(15, 0, 10, 30)).setTo(255);
    return o;
}

bool sameImage(const cv::Mat& a, const cv::Mat& b)
{
    return a.type() == b.type() && a.size() == b.size() &&
           (a.empty() || cv::norm(a, b, cv::NORM_INF) == 0.0);
}

bool samePoints(const std::vector<maps::SemanticPoint>& a,
                const std::vector<maps::SemanticPoint>& b)
{
    if (a.size() != b.size())
        return false;
    for (size_t i = 0; i < a.size(); i++)
        if ((a[i].position - b[i].position).norm() > 1e-6f || a[i].label != b[i].label ||
            a[i].r != b[i].r || std::abs(a[i].confidence - b[i].confidence) > 1e-6f)
            return false;
    return true;
}
}  // namespace

TEST(CObservationSemanticRGBD, SerializationRoundTripAndRawlogByClassName)
{
    const auto o = wallObservation();
    o->sensorPose = mrpt::poses::CPose3D(0.1, 0.2, 0.3, 0.4, 0.5, 0.6);
    test::TempDir dir;
    {
        mrpt::io::CFileGZOutputStream f(dir / "annotated.rawlog");
        auto arch = mrpt::serialization::archiveFrom(f);
        arch << *o;
    }
    mrpt::io::CFileGZInputStream f(dir / "annotated.rawlog");
    auto arch = mrpt::serialization::archiveFrom(f);
    const auto obj = arch.ReadObject();  // by class name, as rawlog readers do
    const auto back = std::dynamic_pointer_cast<CObservationSemanticRGBD>(obj);
    ASSERT_TRUE(back) << obj->GetRuntimeClass()->className;
    EXPECT_EQ(back->sensorLabel, "keyframe");
    EXPECT_EQ(back->timestamp, o->timestamp);
    EXPECT_EQ(back->sensorPose, o->sensorPose);
    EXPECT_EQ(back->camera, o->camera);
    EXPECT_TRUE(sameImage(back->colour, o->colour));
    EXPECT_TRUE(sameImage(back->depth, o->depth));
    EXPECT_TRUE(sameImage(back->labels, o->labels));
    EXPECT_TRUE(sameImage(back->confidence, o->confidence));
    EXPECT_TRUE(sameImage(back->dynamicMask, o->dynamicMask));
    std::ostringstream text;
    back->getDescriptionAsText(text);
    EXPECT_NE(text.str().find("Dynamic pixels: 300"), std::string::npos) << text.str();
}

TEST(CSemanticPointsMap, InsertsStaticPixelsAndFusesLabels)
{
    CSemanticPointsMap map;
    map.insertionOptions.voxel_size = 0.1;
    const auto o = wallObservation();
    // Camera at the origin looking along +Z (optical frame = world): the wall is z = 2.
    ASSERT_TRUE(map.insertObservation(*o, mrpt::poses::CPose3D()));
    // Static pixels: columns 0-14 (person) and 25-39 (chair). At 2 m with f = 40 a pixel is
    // 5 cm, so each 10 cm voxel holds 2 x 2 pixels: 30 x 30 static pixels -> 15 x 8 voxels,
    // with one voxel column split by the dynamic gap ... all at z = 2.
    const auto pts = map.points();
    ASSERT_FALSE(pts.empty());
    int person = 0, chair = 0;
    for (const auto& p : pts)
    {
        EXPECT_NEAR(p.position.z(), 2.0f, 1e-5);
        EXPECT_FALSE(std::abs(p.position.x()) < 0.2f) << "a dynamic pixel was mapped";
        (p.label == 15 ? person : chair)++;
        EXPECT_EQ(p.r, 30);
    }
    EXPECT_GT(person, 0);
    EXPECT_GT(chair, 0);
    EXPECT_EQ(pts.front().label, 15);  // x < 0 voxels first
    EXPECT_NEAR(pts.front().confidence, 1.0f, 1e-6);

    // The same wall seen again with the chair half relabelled person at 0.7: chair 0.6 vs
    // person 0.7 summed -> person wins there with 0.7 / 1.3.
    auto again = wallObservation();
    again->labels.setTo(15);
    again->confidence.setTo(0.7f);
    map.insertObservation(*again, mrpt::poses::CPose3D());
    for (const auto& p : map.points())
    {
        EXPECT_EQ(p.label, 15);
        if (p.position.x() > 0.2f)
        {
            EXPECT_NEAR(p.confidence, 0.7f / 1.3f, 1e-5);
        }
    }
    // Not our observation: refused.
    mrpt::obs::CObservation::Ptr other = mrpt::obs::CObservationOdometry::Create();
    EXPECT_FALSE(map.insertObservation(*other, mrpt::poses::CPose3D()));
}

TEST(CSemanticPointsMap, SerializationAndPlyRoundTrips)
{
    CSemanticPointsMap map;
    map.insertionOptions.voxel_size = 0.05;
    map.insertObservation(*wallObservation(), mrpt::poses::CPose3D(1, 2, 3, 0.3, 0.2, 0.1));
    ASSERT_GT(map.size(), 100u);

    mrpt::io::CMemoryStream buf;
    auto arch = mrpt::serialization::archiveFrom(buf);
    arch << map;
    buf.Seek(0);
    const auto back = std::dynamic_pointer_cast<CSemanticPointsMap>(arch.ReadObject());
    ASSERT_TRUE(back);
    EXPECT_DOUBLE_EQ(back->insertionOptions.voxel_size, 0.05);
    EXPECT_TRUE(samePoints(back->points(), map.points()));

    test::TempDir dir;
    map.saveMetricMapRepresentationToFile(dir / "map");
    CSemanticPointsMap loaded;
    loaded.insertionOptions.voxel_size = 0.05;
    loaded.loadPly(dir / "map.ply");
    EXPECT_TRUE(samePoints(loaded.points(), map.points()));
    EXPECT_NE(test::inputErrorOf([&] { loaded.loadPly(dir / "missing.ply"); }).find("missing.ply"),
              std::string::npos);
}

TEST(CSemanticPointsMap, DeclaredInACMultiMetricMapConfiguration)
{
    mrpt::config::CConfigFileMemory cfg(
        "[map]\n"
        "semanticPointsMap_count = 1\n"
        "[map_semanticPointsMap_00_insertOpts]\n"
        "voxel_size = 0.25\n"
        "max_depth = 3.0\n"
        "[map_semanticPointsMap_00_renderOpts]\n"
        "colour_by_class = false\n");
    mrpt::maps::TSetOfMetricMapInitializers inits;
    inits.loadFromConfigFile(cfg, "map");
    mrpt::maps::CMultiMetricMap multi(inits);
    ASSERT_EQ(multi.maps.size(), 1u);
    const auto ours = multi.mapByClass<CSemanticPointsMap>();
    ASSERT_TRUE(ours);
    EXPECT_DOUBLE_EQ(ours->insertionOptions.voxel_size, 0.25);
    EXPECT_DOUBLE_EQ(ours->insertionOptions.projection.max_depth, 3.0);
    EXPECT_FALSE(ours->renderOptions.colour_by_class);
    // Inserting through the multi-map fills ours.
    EXPECT_TRUE(multi.insertObservation(*wallObservation(), mrpt::poses::CPose3D()));
    EXPECT_GT(ours->size(), 0u);

    mrpt::opengl::CSetOfObjects scene;
    ours->getVisualizationInto(scene);
    const auto cloud = scene.getByClass<mrpt::opengl::CPointCloudColoured>();
    ASSERT_TRUE(cloud);
    EXPECT_EQ(cloud->size(), ours->size());
}
