#include "smap/maps/MapSnapshot.h"

#include <mrpt/opengl/CFBORender.h>
#include <mrpt/opengl/COpenGLScene.h>
#include <mrpt/opengl/CSetOfObjects.h>

#include <algorithm>
#include <cmath>
#include <opencv2/imgproc.hpp>

#include "smap/maps/CSemanticOctoMap.h"
#include "smap/maps/CSemanticPointsMap.h"

namespace smap::maps
{
MapSnapshot::MapSnapshot(SnapshotOptions options) : options_(std::move(options)) {}

cv::Mat MapSnapshot::render(const CSemanticPointsMap& map) const
{
    mrpt::opengl::CSetOfObjects objects;
    map.getVisualizationInto(objects);
    std::set<int> present;
    if (map.renderOptions.colour_by_class)
        for (const auto& p : map.points())
            present.insert(p.label);
    return render(objects, present);
}

cv::Mat MapSnapshot::render(const CSemanticOctoMap& map) const
{
    mrpt::opengl::CSetOfObjects objects;
    map.getVisualizationInto(objects);
    std::set<int> present;
    if (map.renderOptions.colour_by_class)
        for (const auto& v : map.occupiedVoxels())
            present.insert(v.label == 255 ? 0 : v.label);
    return render(objects, present);
}

cv::Mat MapSnapshot::render(const mrpt::opengl::CSetOfObjects& objects,
                            const std::set<int>& legend) const
{
    mrpt::opengl::COpenGLScene scene;
    auto copy = mrpt::opengl::CSetOfObjects::Create(objects);
    scene.insert(copy);
    scene.getViewport()->setCustomBackgroundColor({1.0f, 1.0f, 1.0f, 1.0f});

    // Orbit camera around the bounding box's centre, far enough to see all of it.
    mrpt::math::TBoundingBox box({0, 0, 0}, {1, 1, 1});
    try
    {
        box = copy->getBoundingBox();
    }
    catch (const std::exception&)
    {
        // an empty map: keep the unit box
    }
    const auto centre = (box.min + box.max) * 0.5;
    const double diagonal = std::max(0.5, (box.max - box.min).norm());
    mrpt::opengl::CFBORender fbo(mrpt::opengl::CFBORender::Parameters(
        static_cast<unsigned>(options_.width), static_cast<unsigned>(options_.height)));
    auto& camera = fbo.getCamera(scene);
    camera.set6DOFMode(false);
    camera.setProjectiveModel(true);
    camera.setProjectiveFOVdeg(static_cast<float>(options_.fov_deg));
    camera.setPointingAt(centre);
    camera.setZoomDistance(static_cast<float>(options_.distance_factor * diagonal));
    camera.setAzimuthDegrees(static_cast<float>(options_.azimuth_deg));
    camera.setElevationDegrees(static_cast<float>(options_.elevation_deg));
    scene.getViewport()->setViewportClipDistances(0.01f, static_cast<float>(10.0 * diagonal));

    mrpt::img::CImage rgb;
    fbo.render_RGB(scene, rgb);
    cv::Mat image = rgb.asCvMatRef().clone();  // MRPT images are BGR in memory

    if (options_.legend && !legend.empty())
    {
        int y = 10;
        for (const int id : legend)
        {
            if (id < 0 || id >= static_cast<int>(options_.labels.size()))
                continue;
            const auto& l = options_.labels[static_cast<size_t>(id)];
            cv::rectangle(image, cv::Rect(10, y, 16, 16), l.colourBgr, cv::FILLED);
            cv::rectangle(image, cv::Rect(10, y, 16, 16), cv::Scalar(0, 0, 0), 1);
            cv::putText(image, l.name, cv::Point(32, y + 13), cv::FONT_HERSHEY_SIMPLEX, 0.45,
                        cv::Scalar(0, 0, 0), 1, cv::LINE_AA);
            y += 22;
        }
    }
    return image;
}
}  // namespace smap::maps
