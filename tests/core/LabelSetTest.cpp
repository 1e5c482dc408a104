// classMask: the pixels of chosen classes in a label image.
#include <gtest/gtest.h>

#include <opencv2/core.hpp>
#include <vector>

#include "smap/core/LabelSet.h"

using namespace smap;

TEST(ClassMask, MarksTheChosenClassesOnly)
{
    cv::Mat labels(2, 3, CV_8UC1, cv::Scalar(0));
    labels.at<uint8_t>(0, 1) = 15;                     // person: movable
    labels.at<uint8_t>(1, 0) = 11;                     // dining table: not
    labels.at<uint8_t>(1, 2) = core::LabelSet::kVoid;  // void: never
    const std::vector<bool> movable = core::LabelSet::pascalVoc().movable(0.5);
    const cv::Mat mask = core::classMask(labels, movable);
    ASSERT_EQ(mask.type(), CV_8UC1);
    ASSERT_EQ(mask.size(), labels.size());
    EXPECT_EQ(mask.at<uint8_t>(0, 1), 255);
    EXPECT_EQ(cv::countNonZero(mask), 1);
    std::vector<bool> tables(12, false);
    tables[11] = true;
    EXPECT_EQ(core::classMask(labels, tables).at<uint8_t>(1, 0), 255);
    EXPECT_EQ(cv::countNonZero(core::classMask(labels, {})), 0);
}
