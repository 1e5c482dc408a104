#include "smap/maps/CObservationSemanticRGBD.h"

#include <mrpt/core/format.h>
#include <mrpt/serialization/CArchive.h>

#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <stdexcept>

IMPLEMENTS_SERIALIZABLE(CObservationSemanticRGBD, mrpt::obs::CObservation, smap::maps)

namespace smap::maps
{
namespace
{
/// 8-bit images go as PNG (lossless, compact), float images as raw little-endian floats.
void writeImage(mrpt::serialization::CArchive& out, const cv::Mat& img)
{
    const int type = img.empty() ? -1 : img.type();
    out << static_cast<int32_t>(type) << static_cast<int32_t>(img.rows)
        << static_cast<int32_t>(img.cols);
    if (img.empty())
        return;
    if (img.depth() == CV_8U)
    {
        std::vector<uchar> png;
        if (!cv::imencode(".png", img, png))
            throw std::runtime_error("CObservationSemanticRGBD: cannot encode an image");
        out << static_cast<uint64_t>(png.size());
        out.WriteBuffer(png.data(), png.size());
        return;
    }
    CV_Assert(img.type() == CV_32FC1);
    const cv::Mat c = img.isContinuous() ? img : img.clone();
    out.WriteBufferFixEndianness(c.ptr<float>(), c.total());
}

cv::Mat readImage(mrpt::serialization::CArchive& in)
{
    int32_t type = 0, rows = 0, cols = 0;
    in >> type >> rows >> cols;
    if (type < 0)
        return {};
    if (rows <= 0 || cols <= 0 || rows > 100000 || cols > 100000)
        throw std::runtime_error(
            mrpt::format("CObservationSemanticRGBD: corrupt image header (%d x %d)", cols, rows));
    if (CV_MAT_DEPTH(type) == CV_8U)
    {
        uint64_t bytes = 0;
        in >> bytes;
        if (bytes > 1ull << 32)
            throw std::runtime_error("CObservationSemanticRGBD: corrupt image size");
        std::vector<uchar> png(bytes);
        in.ReadBuffer(png.data(), png.size());
        cv::Mat img = cv::imdecode(png, cv::IMREAD_UNCHANGED);
        if (img.type() != type || img.rows != rows || img.cols != cols)
            throw std::runtime_error("CObservationSemanticRGBD: corrupt PNG image");
        return img;
    }
    if (type != CV_32FC1)
        throw std::runtime_error(mrpt::format("CObservationSemanticRGBD: image type %d", type));
    cv::Mat img(rows, cols, CV_32FC1);
    in.ReadBufferFixEndianness(img.ptr<float>(), img.total());
    return img;
}
}  // namespace

void CObservationSemanticRGBD::validate() const
{
    const cv::Size size(camera.width, camera.height);
    auto check = [&](const cv::Mat& m, int type, const char* what, bool optional)
    {
        if (optional && m.empty())
            return;
        if (m.type() != type || m.size() != size)
            throw std::invalid_argument(mrpt::format(
                "CObservationSemanticRGBD: %s is %dx%d of type %d, expected %dx%d of type %d", what,
                m.cols, m.rows, m.type(), size.width, size.height, type));
    };
    check(colour, CV_8UC3, "colour", false);
    check(depth, CV_32FC1, "depth", false);
    check(labels, CV_8UC1, "labels", false);
    check(confidence, CV_32FC1, "confidence", true);
    check(dynamicMask, CV_8UC1, "dynamic mask", true);
}

mrpt::poses::CPose3D CObservationSemanticRGBD::cameraPose(
    const std::optional<const mrpt::poses::CPose3D>& robotPose) const
{
    return (robotPose ? *robotPose : mrpt::poses::CPose3D()) + sensorPose;
}

std::vector<SemanticPoint> CObservationSemanticRGBD::staticPoints(
    const mrpt::poses::CPose3D& T_world_cam, const BackProjectionParameters& params) const
{
    validate();
    BackProjector projector(params);
    return projector.project({colour, depth, labels, confidence, dynamicMask}, camera, T_world_cam);
}

uint8_t CObservationSemanticRGBD::serializeGetVersion() const
{
    return 0;
}

void CObservationSemanticRGBD::serializeTo(mrpt::serialization::CArchive& out) const
{
    out << timestamp << sensorLabel << sensorPose;
    out << static_cast<int32_t>(camera.width) << static_cast<int32_t>(camera.height) << camera.fx
        << camera.fy << camera.cx << camera.cy;
    for (const double k : camera.distortion)
        out << k;
    for (const cv::Mat* m : {&colour, &depth, &labels, &confidence, &dynamicMask})
        writeImage(out, *m);
}

void CObservationSemanticRGBD::serializeFrom(mrpt::serialization::CArchive& in, uint8_t version)
{
    if (version != 0)
        MRPT_THROW_UNKNOWN_SERIALIZATION_VERSION(version);
    int32_t w = 0, h = 0;
    in >> timestamp >> sensorLabel >> sensorPose;
    in >> w >> h >> camera.fx >> camera.fy >> camera.cx >> camera.cy;
    camera.width = w;
    camera.height = h;
    for (double& k : camera.distortion)
        in >> k;
    for (cv::Mat* m : {&colour, &depth, &labels, &confidence, &dynamicMask})
        *m = readImage(in);
}

void CObservationSemanticRGBD::getDescriptionAsText(std::ostream& o) const
{
    CObservation::getDescriptionAsText(o);
    o << "Semantic RGB-D keyframe (semantic-mapper)\n";
    o << "Camera: " << camera.toString() << "\n";
    o << "Sensor pose on the robot: " << sensorPose << "\n";
    o << "Images: colour " << colour.cols << "x" << colour.rows << ", depth, labels"
      << (confidence.empty() ? "" : ", label confidence")
      << (dynamicMask.empty() ? "" : ", dynamic mask") << "\n";
    if (!dynamicMask.empty())
        o << "Dynamic pixels: " << cv::countNonZero(dynamicMask) << "\n";
}
}  // namespace smap::maps
