#include <gtest/gtest.h>
#include <mrpt/obs/CObservation3DRangeScan.h>

#include <cmath>
#include <string>

#include "SyntheticRgbd.h"
#include "smap/core/InputError.h"
#include "smap/io/RgbdObservationConverter.h"

using namespace smap;

// A live sensor's observation, never written to a file: a plane at z = 1.5 m in raw units of
// 0.1 mm becomes 1.5 m of depth everywhere, with the observation's camera and timestamp.
TEST(RgbdObservationConverter, ObservationInMemoryBecomesAFrameInMetres)
{
    const auto cam = test::smallCamera();
    cv::Mat raw(48, 64, CV_16UC1, cv::Scalar(15000));
    auto o =
        test::makeCoincidentObservation(cam, test::patternColour(64, 48, 3), raw, 0.0001f, 12.5);
    io::RgbdObservationConverter converter({});
    const core::RgbdFrame f = converter.convert(*o, "sensor 'KINECT'");
    EXPECT_EQ(f.camera, cam);
    EXPECT_NEAR(f.timestamp, 12.5, 1e-6);
    ASSERT_EQ(f.depth.size(), cv::Size(64, 48));
    double lo = 0, hi = 0;
    cv::minMaxLoc(f.depth, &lo, &hi);
    EXPECT_NEAR(lo, 1.5, 1e-4);
    EXPECT_NEAR(hi, 1.5, 1e-4);
    EXPECT_EQ(cv::norm(f.colour, test::patternColour(64, 48, 3), cv::NORM_INF), 0.0);
}

// What cannot become a frame is an input error naming where the observation came from.
TEST(RgbdObservationConverter, ObservationWithoutDepthOrColourIsAnErrorNamingItsSource)
{
    const auto cam = test::smallCamera();
    io::RgbdObservationConverter converter({});
    auto empty =
        test::makeCoincidentObservation(cam, test::patternColour(64, 48, 0),
                                        cv::Mat(48, 64, CV_16UC1, cv::Scalar(0)), 0.0001f, 1.0);
    try
    {
        converter.convert(*empty, "sensor 'KINECT'");
        FAIL() << "a range image of zeros has no depth";
    }
    catch (const core::InputError& e)
    {
        EXPECT_NE(
            std::string(e.what()).find("sensor 'KINECT': the range image holds no valid depth"),
            std::string::npos)
            << e.what();
    }
    auto noColour =
        test::makeCoincidentObservation(cam, test::patternColour(64, 48, 0),
                                        cv::Mat(48, 64, CV_16UC1, cv::Scalar(9000)), 0.0001f, 1.0);
    noColour->hasIntensityImage = false;
    try
    {
        converter.convert(*noColour, "sensor 'KINECT'");
        FAIL() << "no intensity image";
    }
    catch (const core::InputError& e)
    {
        EXPECT_NE(std::string(e.what()).find("sensor 'KINECT': CObservation3DRangeScan"),
                  std::string::npos)
            << e.what();
        EXPECT_NE(std::string(e.what()).find("lacks its intensity image"), std::string::npos)
            << e.what();
    }
}
