#include <gtest/gtest.h>

#include <opencv2/imgcodecs.hpp>

#include "TestData.h"
#include "TrajectoryHelpers.h"
#include "smap/eval/EvalReport.h"
#include "smap/eval/TrajectoryPlot.h"

using namespace smap;

TEST(TrajectoryPlot, DrawsBothTrajectoriesAndWritesAPng)
{
    const auto gt = test::curve(300);
    auto est = gt;
    for (size_t i = 0; i < est.size(); i++)
        est[i].T_world_cam.x_incr(0.05 * std::sin(0.1 * i));
    const auto ate = eval::computeAte(gt, est);
    const cv::Mat img = eval::renderAtePlot(ate);
    ASSERT_EQ(img.type(), CV_8UC3);
    EXPECT_EQ(img.cols, 1100);
    // Pixels of the estimate's colour (BGR 200,110,20) and of the error lines must be present.
    cv::Mat estMask, errMask;
    cv::inRange(img, cv::Scalar(190, 100, 10), cv::Scalar(210, 120, 30), estMask);
    cv::inRange(img, cv::Scalar(50, 50, 220), cv::Scalar(70, 70, 240), errMask);
    EXPECT_GT(cv::countNonZero(estMask), 500);
    EXPECT_GT(cv::countNonZero(errMask), 50);

    test::TempDir dir;
    eval::saveAtePlot(dir / "ate.png", ate);
    const cv::Mat back = cv::imread(dir / "ate.png");
    EXPECT_EQ(back.size(), img.size());
}

TEST(EvalReport, JsonHasTheDocumentedKeys)
{
    const auto gt = test::curve(100);
    const auto r = eval::computeAte(gt, gt);
    const std::string j = eval::ateToJson(r, {}).dump();
    for (const char* k : {"\"rmse\"", "\"mean\"", "\"median\"", "\"std\"", "\"min\"", "\"max\"",
                          "\"pairs\": 100", "\"coverage\": 1"})
        EXPECT_NE(j.find(k), std::string::npos) << k << " in " << j;
    EXPECT_NE(j.find("\"longest_gap\""), std::string::npos) << j;
    EXPECT_NE(j.find("\"poses\": 0"), std::string::npos) << j;
    EXPECT_EQ(j.find("\"first_row\""), std::string::npos) << j;
    EXPECT_EQ(eval::ateToText(r).find("longest gap"), std::string::npos);
    const core::Trajectory early(gt.begin(), gt.begin() + 90);
    const auto cut = eval::computeAte(gt, early);
    const std::string cj = eval::ateToJson(cut, {}).dump();
    EXPECT_NE(cj.find("\"poses\": 10"), std::string::npos) << cj;
    EXPECT_NE(cj.find("\"first_row\": 90"), std::string::npos) << cj;
    EXPECT_NE(eval::ateToText(cut).find(
                  "longest gap 10 ground-truth poses without an estimate (rows 90-99"),
              std::string::npos)
        << eval::ateToText(cut);
    const std::string rj = eval::rpeToJson(eval::computeRpe(gt, gt), {}).dump();
    EXPECT_NE(rj.find("\"translation\""), std::string::npos);
    EXPECT_NE(rj.find("\"delta_unit\": \"s\""), std::string::npos);
}
