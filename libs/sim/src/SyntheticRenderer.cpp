#include "smap/sim/SyntheticRenderer.h"

#include <mrpt/img/CImage.h>
#include <mrpt/opengl/CFBORender.h>
#include <mrpt/opengl/COpenGLScene.h>
#include <mrpt/opengl/CSetOfTexturedTriangles.h>
#include <mrpt/opengl/CSetOfTriangles.h>

#include <stdexcept>

namespace smap::sim
{
namespace
{
using mrpt::opengl::TTriangle;

TTriangle::Vertex vertex(const Eigen::Vector3f& p, float u, float v, const mrpt::img::TColor& c)
{
    TTriangle::Vertex x;
    x.xyzrgba.pt = {p.x(), p.y(), p.z()};
    x.setColor(c);
    x.uv = {u, v};
    return x;
}

/// Two triangles per quad, with texture coordinates from the quad's window.
std::vector<TTriangle> triangles(const SceneObject& o, const mrpt::img::TColor& c)
{
    std::vector<TTriangle> out;
    for (const auto& q : o.quads)
    {
        const float u0 = q.uv[0], v0 = q.uv[1], u1 = q.uv[2], v1 = q.uv[3];
        TTriangle a, b;
        a.vertices = {vertex(q.corners[0], u0, v0, c), vertex(q.corners[1], u1, v0, c),
                      vertex(q.corners[2], u1, v1, c)};
        b.vertices = {vertex(q.corners[0], u0, v0, c), vertex(q.corners[2], u1, v1, c),
                      vertex(q.corners[3], u0, v1, c)};
        a.computeNormals();
        b.computeNormals();
        out.push_back(a);
        out.push_back(b);
    }
    return out;
}

/// Label colour: R = class, G = instance (the static objects; people are drawn afterwards).
mrpt::img::TColor labelColour(const SceneObject& o)
{
    return {o.classId, static_cast<uint8_t>(o.instanceId & 0xFF), 0, 255};
}

}  // namespace

struct SyntheticRenderer::Impl
{
    const SyntheticScene& scene;
    core::PinholeCamera camera;
    double clipFar;
    mrpt::opengl::COpenGLScene colourScene, labelScene;
    std::unique_ptr<mrpt::opengl::CFBORender> fbo;

    Impl(const SyntheticScene& s, const core::PinholeCamera& cam, double clipNear, double far)
        : scene(s), camera(cam), clipFar(far)
    {
        if (cam.hasDistortion())
            throw std::invalid_argument("SyntheticRenderer renders undistorted images only");
        std::vector<mrpt::img::CImage> textures;
        for (const auto& t : s.textures())
            textures.emplace_back(t, mrpt::img::DEEP_COPY);
        auto addObject = [&](const SceneObject& o)
        {
            auto textured = mrpt::opengl::CSetOfTexturedTriangles::Create();
            for (const auto& tr : triangles(o, {255, 255, 255, 255}))
                textured->insertTriangle(tr);
            textured->assignImage(textures.at(static_cast<size_t>(o.textureIndex)));
            // Unlit: the procedural textures carry the appearance (MRPT's default light is dim).
            textured->enableLight(false);
            textured->setPose(o.T_world_object);
            colourScene.insert(textured);
            auto flat = mrpt::opengl::CSetOfTriangles::Create();
            flat->enableLight(false);
            for (const auto& tr : triangles(o, labelColour(o)))
                flat->insertTriangle(tr);
            flat->setPose(o.T_world_object);
            labelScene.insert(flat);
        };
        for (const auto& o : s.staticObjects())
            addObject(o);
        for (auto* sc : {&colourScene, &labelScene})
        {
            sc->getViewport()->setViewportClipDistances(static_cast<float>(clipNear),
                                                        static_cast<float>(far));
            sc->getViewport()->setCustomBackgroundColor({0.0f, 0.0f, 0.0f, 1.0f});
        }
        fbo = std::make_unique<mrpt::opengl::CFBORender>(mrpt::opengl::CFBORender::Parameters(
            static_cast<unsigned>(cam.width), static_cast<unsigned>(cam.height)));
        // MRPT's renderer puts pixel centres at +0.5; shift the principal point so that pixel
        // (u, v) is centred on (u, v) as everywhere else in semantic-mapper.
        core::PinholeCamera renderCam = cam;
        renderCam.cx += 0.5;
        renderCam.cy += 0.5;
        auto& c = fbo->getCamera(colourScene);
        c.set6DOFMode(true);
        c.setProjectiveFromPinhole(renderCam.toMrpt());
    }
};

SyntheticRenderer::SyntheticRenderer(const SyntheticScene& scene, const core::PinholeCamera& camera,
                                     double clipNear, double clipFar)
    : impl_(std::make_unique<Impl>(scene, camera, clipNear, clipFar))
{
}

SyntheticRenderer::~SyntheticRenderer() = default;

RenderedFrame SyntheticRenderer::render(double t, const mrpt::poses::CPose3D& T_world_cam,
                                        double motionDt)
{
    auto& I = *impl_;
    I.fbo->getCamera(I.colourScene).setPose(T_world_cam);
    RenderedFrame f;
    mrpt::img::CImage rgb, labelRgb;
    mrpt::math::CMatrixFloat depth;
    I.fbo->render_RGBD(I.colourScene, rgb, depth);
    I.fbo->render_RGB(I.labelScene, labelRgb);
    f.colour = rgb.asCvMatRef().clone();
    f.depth.create(I.camera.height, I.camera.width, CV_32FC1);
    for (int v = 0; v < f.depth.rows; v++)
    {
        for (int u = 0; u < f.depth.cols; u++)
        {
            const float z = depth(v, u);
            f.depth.at<float>(v, u) =
                (z > 0.0f && z < 0.999f * static_cast<float>(I.clipFar)) ? z : 0.0f;
        }
    }
    const cv::Mat& lab = labelRgb.asCvMatRef();  // BGR: G = instance, R = class
    f.labels.create(lab.size(), CV_8UC1);
    f.instances.create(lab.size(), CV_16UC1);
    f.dynamic = cv::Mat::zeros(lab.size(), CV_8UC1);
    for (int v = 0; v < lab.rows; v++)
    {
        for (int u = 0; u < lab.cols; u++)
        {
            const cv::Vec3b c = lab.at<cv::Vec3b>(v, u);
            f.labels.at<uint8_t>(v, u) = c[2];
            f.instances.at<uint16_t>(v, u) = c[1];
        }
    }

    // People over the rendered room, each tested against its depth and against each other.
    BillboardLayers layers{f.colour, f.depth, f.labels, f.instances, f.dynamic};
    for (const auto& p : I.scene.people())
    {
        const BillboardPose now = p.billboard(t);
        const BillboardPose before = p.billboard(t - motionDt);
        I.scene.personSprites()
            .at(p.spec().sprite)
            .draw(now, &before, I.camera, T_world_cam, voc::kPerson, p.instanceId(), layers);
    }
    return f;
}
}  // namespace smap::sim
