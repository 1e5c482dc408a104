#include <gtest/gtest.h>
#include <mrpt/core/format.h>

#include <filesystem>
#include <fstream>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "TestData.h"
#include "smap/apps/EvalApp.h"
#include "smap/core/InputError.h"

using namespace smap;

namespace
{
void writeFile(const std::string& path, const std::string& text)
{
    std::ofstream(path) << text;
}

/// `smap-eval keypoints` input folders dir/masks and dir/debug, with a `size` x `size` px mask
/// whose columns 0-4 are a person for each of `frames` (file stems).
void writePersonMasks(const test::TempDir& dir, int size, const std::vector<std::string>& frames)
{
    std::filesystem::create_directories(dir / "masks");
    std::filesystem::create_directories(dir / "debug");
    cv::Mat mask(size, size, CV_8UC1, cv::Scalar(0));
    mask.colRange(0, 5).setTo(255);
    for (const std::string& frame : frames)
        ASSERT_TRUE(cv::imwrite(dir / ("masks/" + frame + ".png"), mask));
}
}  // namespace

TEST(EvalApp, AteWritesJsonAndPlot)
{
    test::TempDir dir;
    // Ground truth on a square; the estimate is the same square shifted by 1 m in x with one
    // pose 0.3 m off: after alignment the errors are known in closed form only roughly, but
    // the maximum must sit on that pose and the RMSE must be non-zero.
    std::string gt, est;
    const double xy[5][2] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}, {0.5, 0.5}};
    for (int i = 0; i < 5; i++)
    {
        gt += std::to_string(i) + " " + std::to_string(xy[i][0]) + " " + std::to_string(xy[i][1]) +
              " 0 0 0 0 1\n";
        est += std::to_string(i + 0.01) + " " +
               std::to_string(xy[i][0] + 1 + (i == 4 ? 0.3 : 0.0)) + " " +
               std::to_string(xy[i][1]) + " 0 0 0 0 1\n";
    }
    writeFile(dir / "gt.txt", gt);
    writeFile(dir / "est.txt", est);
    std::ostringstream out;
    apps::EvalApp app;
    EXPECT_EQ(app.run({"ate", dir / "gt.txt", dir / "est.txt", "--json", dir / "ate.json", "--plot",
                       dir / "ate.png"},
                      out),
              0);
    const std::string j = smap::test::readTextFile(dir / "ate.json");
    for (const char* k : {"\"rmse\"", "\"mean\"", "\"median\"", "\"std\"", "\"min\"", "\"max\"",
                          "\"pairs\": 5", "\"coverage\": 1"})
        EXPECT_NE(j.find(k), std::string::npos) << k;
    EXPECT_TRUE(std::filesystem::exists(dir / "ate.png"));
    EXPECT_NE(out.str().find("rmse"), std::string::npos);
    // Translating the outlier by 0.3 along x: the aligned errors are 0.3 * (4/5) on it and 0.3/5 on
    // the others.
    EXPECT_NE(out.str().find(mrpt::format("max     %.6f", 0.24)), std::string::npos) << out.str();
}

TEST(EvalApp, RpeAndArgumentErrors)
{
    test::TempDir dir;
    std::string gt;
    for (int i = 0; i < 40; i++)
        gt += std::to_string(i * 0.1) + " " + std::to_string(i * 0.01) + " 0 0 0 0 0 1\n";
    writeFile(dir / "gt.txt", gt);
    std::ostringstream out;
    apps::EvalApp app;
    EXPECT_EQ(app.run({"rpe", dir / "gt.txt", dir / "gt.txt", "--delta", "5", "--delta-unit",
                       "frames", "--json", dir / "rpe.json"},
                      out),
              0);
    EXPECT_NE(smap::test::readTextFile(dir / "rpe.json").find("\"delta_unit\": \"frames\""),
              std::string::npos);
    EXPECT_THROW(app.run({"ate", dir / "gt.txt"}, out), core::InputError);
    EXPECT_THROW(app.run({"rpe", dir / "gt.txt", dir / "gt.txt", "--plot", "x.png"}, out),
                 core::InputError);
    EXPECT_THROW(app.run({"ate", dir / "gt.txt", dir / "missing.txt"}, out), core::InputError);
    EXPECT_THROW(app.run({"ate", dir / "gt.txt", dir / "gt.txt", "--max-dt", "abc"}, out),
                 core::InputError);
}

TEST(EvalApp, KeypointsSaysWhereTheFalsePositivesAre)
{
    test::TempDir dir;
    // Columns 0-4 of a 20 x 20 image are a person.
    writePersonMasks(dir, 20, {"000001"});
    writeFile(dir / "debug/000001.csv",
              "u,v,depth_m,residual_px,patch_error,flow,depth_test,region,isolated,was_dynamic,"
              "semantic,dynamic\n"
              "2,2,1,9,1,1,0,0,0,0,1,1\n"      // true positive
              "5,8,1,0.5,1,0,0,1,0,0,0,1\n"    // 1 px from the person, by region growing
              "6,3,1,9,1,1,0,0,0,0,1,1\n"      // 2 px, by flow (and semantic evidence)
              "15,10,1,0.5,1,0,0,0,0,0,1,1\n"  // 11 px, by semantic evidence alone
              "18,18,1,0.5,1,0,0,0,0,0,0,0\n");
    std::ostringstream out;
    apps::EvalApp app;
    ASSERT_EQ(app.run({"keypoints", dir / "masks", dir / "debug", "--json", dir / "k.json"}, out),
              0);
    EXPECT_NE(out.str().find("recall 1.0000  precision 0.2500  (tp 1 fp 3 fn 0 tn 1)"),
              std::string::npos)
        << out.str();
    EXPECT_NE(out.str().find("<= 1.5 px 1, 1.5-3 px 1, 3-10 px 0, 10-50 px 1, farther 0"),
              std::string::npos)
        << out.str();
    EXPECT_NE(out.str().find("flow 1, depth 0, region 1, semantic only 1, other 0"),
              std::string::npos)
        << out.str();
    // Only the two outline false positives left: 1 / (1 + 2).
    EXPECT_NE(out.str().find("within 3 px of a mask remained: 0.3333"), std::string::npos)
        << out.str();
    const std::string json = test::readTextFile(dir / "k.json");
    EXPECT_NE(json.find("\"up_to_50_px\": 1"), std::string::npos) << json;
    EXPECT_NE(json.find("\"semantic_only\": 1"), std::string::npos) << json;
}

TEST(EvalApp, KeypointsSplitsTheOutlineBandBySide)
{
    test::TempDir dir;
    // Columns 0-4 of a 20 x 20 image are a person: the 3 px band is columns 2-4 on the person
    // and 5-7 beside it.
    writePersonMasks(dir, 20, {"000001"});
    writeFile(dir / "debug/000001.csv",
              "u,v,depth_m,residual_px,patch_error,flow,depth_test,region,isolated,was_dynamic,"
              "semantic,dynamic\n"
              "3,1,1,9,1,1,0,0,0,0,0,1\n"     // band, on the person, said
              "4,5,0,0.5,1,0,0,0,0,0,0,0\n"   // band, on the person, not said
              "1,9,1,9,1,1,0,0,0,0,0,1\n"     // on the person, outside the band
              "6,2,0,9,1,1,0,0,0,0,0,1\n"     // band, beside, said
              "7,7,1,0.5,1,0,0,0,0,0,0,0\n"   // band, beside, not said
              "7,12,1,0.5,1,0,0,0,0,0,0,0\n"  // band, beside, not said
              "8,4,1,9,1,1,0,0,0,0,0,1\n");   // beside, outside the band
    apps::EvalApp app;
    // The band is counted whether or not the edge margin leaves it out of the score.
    for (const char* margin : {"0", "3"})
    {
        std::ostringstream out;
        ASSERT_EQ(app.run({"keypoints", dir / "masks", dir / "debug", "--edge-margin", margin,
                           "--json", dir / "k.json"},
                          out),
                  0);
        EXPECT_NE(out.str().find("said dynamic 50.0 % of 2 keypoints on a mask, 33.3 % of 3 "
                                 "beside one"),
                  std::string::npos)
            << "margin " << margin << ": " << out.str();
        const std::string json = test::readTextFile(dir / "k.json");
        EXPECT_NE(json.find("\"beside_mask_said_dynamic\": 1"), std::string::npos) << json;
        EXPECT_NE(json.find("\"on_mask_keypoints\": 2"), std::string::npos) << json;
        // One keypoint on the person off the band, two on it in the band, three beside. Recall
        // 0.95 needs 0.95 x 3 - 1 = 1.85 of the band's two on the person, a rate of 0.925,
        // which says 2.775 of the three beside: precision 2.85 / 5.625.
        EXPECT_NE(out.str().find("recall 0.95 leaves precision 0.5067 at best (1 keypoints"),
                  std::string::npos)
            << out.str();
        EXPECT_NE(json.find("\"mask_keypoints_off_band\": 1"), std::string::npos) << json;
        EXPECT_NE(json.find("\"best_precision_at_recall_0.95\": 0.50"), std::string::npos) << json;
    }
}

TEST(EvalApp, KeypointsScoresWhatASegmentationWouldDecide)
{
    test::TempDir dir;
    // Columns 0-4 of a 20 x 20 image are a person (the 3 px band: columns 2-4 on the person,
    // 5-7 beside it); the segmentation's person (VOC id 15) reaches one column too far, to 5.
    writePersonMasks(dir, 20, {"000001"});
    std::filesystem::create_directories(dir / "labels");
    cv::Mat labels(20, 20, CV_8UC1, cv::Scalar(0));
    labels.colRange(0, 6).setTo(15);
    ASSERT_TRUE(cv::imwrite(dir / "labels/000001.png", labels));
    writeFile(dir / "debug/000001.csv",
              "u,v,depth_m,residual_px,patch_error,flow,depth_test,region,isolated,was_dynamic,"
              "semantic,dynamic\n"
              "3,1,1,9,1,1,0,0,0,0,0,1\n"       // band, on the person: table yes, labels yes
              "4,5,0,0.5,1,0,0,0,0,0,0,0\n"     // band, on the person: table no, labels yes
              "1,9,1,9,1,1,0,0,0,0,0,1\n"       // on the person off the band: both yes
              "6,2,0,9,1,1,0,0,0,0,0,1\n"       // band, beside: table yes, labels no
              "7,7,1,0.5,1,0,0,0,0,0,0,0\n"     // band, beside: both no
              "7,12,1,0.5,1,0,0,0,0,0,0,0\n"    // band, beside: both no
              "8,4,1,9,1,1,0,0,0,0,0,1\n"       // beside off the band: table yes, labels no
              "5,15,1,0.5,1,0,0,0,0,0,0,0\n");  // band, beside: table no, labels yes
    apps::EvalApp app;
    std::ostringstream out;
    ASSERT_EQ(app.run({"keypoints", dir / "masks", dir / "debug", "--said-by", dir / "labels",
                       "--json", dir / "k.json"},
                      out),
              0);
    const std::string text = out.str();
    const size_t inBand = text.find("within 3 px of a mask edge by the label images");
    ASSERT_NE(inBand, std::string::npos) << text;
    // By the labels alone: every person keypoint found, (5, 15) the one false positive, 1 px
    // from the person, decided by neither flow nor depth nor region.
    EXPECT_LT(text.find("recall 1.0000  precision 0.7500  (tp 3 fp 1 fn 0 tn 4)"), inBand) << text;
    EXPECT_LT(text.find("<= 1.5 px 1, 1.5-3 px 0, 3-10 px 0, 10-50 px 0, farther 0"), inBand)
        << text;
    EXPECT_LT(text.find("other 1"), inBand) << text;
    EXPECT_LT(text.find("said dynamic 100.0 % of 2 keypoints on a mask, 25.0 % of 4 beside"),
              inBand)
        << text;
    // The table off the band, the labels in it: (8, 4) is the table's false positive.
    EXPECT_NE(text.find("recall 1.0000  precision 0.6000  (tp 3 fp 2 fn 0 tn 3)", inBand),
              std::string::npos)
        << text;
    const std::string json = test::readTextFile(dir / "k.json");
    EXPECT_NE(json.find("\"labels\""), std::string::npos) << json;
    EXPECT_NE(json.find("\"labels_in_band\""), std::string::npos) << json;

    // Another class finds nothing; the table's own decisions are unchanged without --said-by.
    std::ostringstream chair;
    ASSERT_EQ(app.run({"keypoints", dir / "masks", dir / "debug", "--said-by", dir / "labels",
                       "--classes", "chair"},
                      chair),
              0);
    EXPECT_NE(chair.str().find("recall 0.0000  precision 1.0000  (tp 0 fp 0 fn 3 tn 5)"),
              std::string::npos)
        << chair.str();
    std::ostringstream table;
    ASSERT_EQ(app.run({"keypoints", dir / "masks", dir / "debug"}, table), 0);
    EXPECT_NE(table.str().find("(tp 2 fp 2 fn 1 tn 3)"), std::string::npos) << table.str();

    // --classes without --said-by, --said-by elsewhere, a missing or misfit label image.
    EXPECT_THROW(app.run({"keypoints", dir / "masks", dir / "debug", "--classes", "person"}, out),
                 core::InputError);
    EXPECT_THROW(app.run({"ate", dir / "a.txt", dir / "b.txt", "--said-by", dir / "labels"}, out),
                 core::InputError);
    ASSERT_TRUE(cv::imwrite(dir / "labels/000001.png", cv::Mat(10, 20, CV_8UC1, cv::Scalar(15))));
    EXPECT_THROW(
        app.run({"keypoints", dir / "masks", dir / "debug", "--said-by", dir / "labels"}, out),
        core::InputError);
    std::filesystem::remove(dir / "labels/000001.png");
    try
    {
        app.run({"keypoints", dir / "masks", dir / "debug", "--said-by", dir / "labels"}, out);
        FAIL() << "expected an InputError";
    }
    catch (const core::InputError& e)
    {
        EXPECT_NE(std::string(e.what()).find("no label image"), std::string::npos) << e.what();
    }
}

TEST(EvalApp, KeypointsScoresDecisionsAgainstMasks)
{
    test::TempDir dir;
    // Left half of a 10x10 image is dynamic.
    writePersonMasks(dir, 10, {"000001", "000002", "000000"});
    const std::string header =
        "u,v,depth_m,residual_px,patch_error,flow,depth_test,region,isolated,was_dynamic,dynamic\n";
    // Frame 0 was not evaluated: it must not count (its all-static rows would be misses).
    writeFile(dir / "debug/000000.csv",
              "# not evaluated (no previous frame): no decision was made\n" + header +
                  "2,2,1,-1,-1,0,0,0,0,0\n");
    // Frame 1: one of each outcome. Frame 2: two true positives, one true negative.
    writeFile(dir / "debug/000001.csv", header +
                                            "2.2,2,1,9,1,1,0,0,0,1\n"    // TP
                                            "7,2,1,9,1,1,0,0,0,1\n"      // FP
                                            "2,7.4,1,0.5,1,0,0,0,0,0\n"  // FN
                                            "7,7,1,0.5,1,0,0,0,0,0\n");  // TN
    writeFile(dir / "debug/000002.csv", header +
                                            "1,1,1,9,1,1,0,0,0,1\n"
                                            "4,9,1,9,1,0,1,0,0,1\n"
                                            "9,9,1,0.1,1,0,0,0,0,0\n");
    std::ostringstream out;
    apps::EvalApp app;
    ASSERT_EQ(app.run({"keypoints", dir / "masks", dir / "debug", "--json", dir / "k.json"}, out),
              0);
    EXPECT_NE(out.str().find("frames 2  recall 0.7500  precision 0.7500"), std::string::npos)
        << out.str();
    const std::string json = test::readTextFile(dir / "k.json");
    EXPECT_NE(json.find("\"true_positives\": 3"), std::string::npos) << json;
    EXPECT_NE(json.find("\"false_negatives\": 1"), std::string::npos) << json;

    // An edge margin of 1 px leaves out the keypoints next to the mask edge (columns 4 and 5):
    // frame 2's (4, 9) true positive; frame 1's are 2 or more px away.
    std::ostringstream margin;
    ASSERT_EQ(app.run({"keypoints", dir / "masks", dir / "debug", "--edge-margin", "1"}, margin),
              0);
    EXPECT_NE(margin.str().find("frames 2  recall 0.6667  precision 0.6667  (tp 2 fp 1 fn 1 tn "
                                "2)  left out within 1 px of a mask edge: 1"),
              std::string::npos)
        << margin.str();
    // 3 px: every keypoint of column 2 or 7 is near the edge too; only the corners' (1, 1)
    // and (9, 9) stay.
    std::ostringstream wide;
    ASSERT_EQ(app.run({"keypoints", dir / "masks", dir / "debug", "--edge-margin", "3"}, wide), 0);
    EXPECT_NE(wide.str().find("(tp 1 fp 0 fn 0 tn 1)  left out within 3 px of a mask edge: 5"),
              std::string::npos)
        << wide.str();
    EXPECT_THROW(app.run({"keypoints", dir / "masks", dir / "debug", "--edge-margin", "-1"}, out),
                 core::InputError);
    EXPECT_THROW(app.run({"ate", dir / "a.txt", dir / "b.txt", "--edge-margin", "1"}, out),
                 core::InputError);

    // A keypoint outside the mask, or a missing mask, is an input error naming the file.
    writeFile(dir / "debug/000003.csv", header + "12,2,1,9,1,1,0,0,0,1\n");
    writePersonMasks(dir, 10, {"000003"});
    try
    {
        app.run({"keypoints", dir / "masks", dir / "debug"}, out);
        FAIL() << "expected an InputError";
    }
    catch (const core::InputError& e)
    {
        EXPECT_NE(std::string(e.what()).find("000003.csv' line 2"), std::string::npos) << e.what();
    }
    std::filesystem::remove(dir / "masks/000003.png");
    EXPECT_THROW(app.run({"keypoints", dir / "masks", dir / "debug"}, out), core::InputError);
}
