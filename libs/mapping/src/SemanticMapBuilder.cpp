#include "smap/mapping/SemanticMapBuilder.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <memory>

#include "BodyVoxels.h"
#include "KeyFrameVoxels.h"
#include "LatestView.h"
#include "MoverVoxels.h"

namespace smap::mapping
{
namespace
{
constexpr double kRadToDeg = 57.29577951308232;

/// Rotation angle (deg) and translation (m) of the relative pose a^-1 b.
std::pair<double, double> poseDifference(const mrpt::poses::CPose3D& a,
                                         const mrpt::poses::CPose3D& b)
{
    const mrpt::poses::CPose3D d = b - a;
    const auto R = d.getRotationMatrix().asEigen();
    const double c = std::clamp((R.trace() - 1.0) / 2.0, -1.0, 1.0);
    return {d.translation().norm(), std::acos(c) * kRadToDeg};
}
}  // namespace

SemanticMapBuilder::SemanticMapBuilder(const MapBuilderParameters& params,
                                       const core::LabelSet& labels)
    : params_(params),
      projector_(params.pointsMap.projection),
      movable_(labels.movable(params.movable_body_prior))
{
    pointsMap_.insertionOptions = params_.pointsMap;
    octoMap_.insertionOptions = params_.octoMap;
    pointsMap_.setLabels(labels);
    octoMap_.setLabels(labels);
}

const KeyFrameContribution& SemanticMapBuilder::add(uint64_t keyframe, uint64_t frameId,
                                                    double timestamp,
                                                    const maps::BackProjector::Images& images,
                                                    const core::PinholeCamera& camera,
                                                    const mrpt::poses::CPose3D& T_world_cam)
{
    KeyFrameContribution c;
    c.keyframe = keyframe;
    c.frameId = frameId;
    c.timestamp = timestamp;
    c.T_world_cam = T_world_cam;
    c.camera = camera;
    std::vector<maps::SemanticPoint> cam =
        projector_.project(images, camera, mrpt::poses::CPose3D());
    if (params_.contribution_voxel > 0.0)
    {
        // One point per voxel of the camera frame: mean position and colour, the class with the
        // highest summed confidence.
        maps::CSemanticPointsMap thin;
        thin.insertionOptions.voxel_size = params_.contribution_voxel;
        thin.insertPoints(cam);
        cam = thin.points();
    }
    c.points_cam = std::move(cam);
    c.points_cam.shrink_to_fit();
    if (params_.prune_near_movers > 0.0)
        c.movers_cam = moverSamples(images, camera);
    if (params_.movable_body_radius > 0.0)
        c.bodies_cam = BodyVoxels::samples(images, camera, movable_, params_.movable_body_erosion);
    if (params_.prune_near_movers > 0.0 && params_.see_through_margin > 0.0)
        c.static_depth_cells = LatestView::staticDepthCells(
            images, params_.pointsMap.projection.min_depth, params_.pointsMap.projection.max_depth);
    insert(c);
    contributions_.push_back(std::move(c));
    return contributions_.back();
}

std::vector<maps::SemanticPoint> SemanticMapBuilder::toWorld(const KeyFrameContribution& c)
{
    std::vector<maps::SemanticPoint> world;
    world.reserve(c.points_cam.size());
    for (const auto& p : c.points_cam)
    {
        maps::SemanticPoint w = p;
        double x = 0, y = 0, z = 0;
        c.T_world_cam.composePoint(p.position.x(), p.position.y(), p.position.z(), x, y, z);
        w.position =
            Eigen::Vector3f(static_cast<float>(x), static_cast<float>(y), static_cast<float>(z));
        world.push_back(w);
    }
    return world;
}

void SemanticMapBuilder::insert(const KeyFrameContribution& c, const std::vector<bool>* keep)
{
    std::vector<maps::SemanticPoint> world = toWorld(c);
    std::vector<float> depth;  // camera-frame z of each kept point
    depth.reserve(world.size());
    size_t kept = 0;
    for (size_t i = 0; i < world.size(); ++i)
    {
        if (keep && !(*keep)[i])
            continue;
        world[kept++] = world[i];
        depth.push_back(c.points_cam[i].position.z());
    }
    world.resize(kept);
    if (params_.points_map)
        pointsMap_.insertPoints(world);
    if (params_.octomap)
    {
        // The octomap's own depth range applies to its rays.
        const auto& proj = params_.octoMap.projection;
        std::vector<maps::SemanticPoint> rays;
        rays.reserve(world.size());
        for (size_t i = 0; i < world.size(); ++i)
        {
            if (depth[i] >= proj.min_depth && depth[i] <= proj.max_depth)
                rays.push_back(world[i]);
        }
        octoMap_.insertPoints(rays, Eigen::Vector3f(static_cast<float>(c.T_world_cam.x()),
                                                    static_cast<float>(c.T_world_cam.y()),
                                                    static_cast<float>(c.T_world_cam.z())));
    }
}

SemanticMapBuilder::ReanchorResult SemanticMapBuilder::reanchor(
    const std::function<std::optional<mrpt::poses::CPose3D>(const KeyFrameContribution&)>&
        finalPose,
    const std::function<bool(const KeyFrameContribution&)>& discard)
{
    ReanchorResult r;
    if (discard)
    {
        const auto end = std::remove_if(contributions_.begin(), contributions_.end(), discard);
        r.discarded = static_cast<size_t>(contributions_.end() - end);
        contributions_.erase(end, contributions_.end());
    }
    std::vector<mrpt::poses::CPose3D> poses;
    poses.reserve(contributions_.size());
    for (const auto& c : contributions_)
    {
        const auto p = finalPose(c);
        poses.push_back(p ? *p : c.T_world_cam);
        const auto [dt, dr] = poseDifference(c.T_world_cam, poses.back());
        r.maxTranslation = std::max(r.maxTranslation, dt);
        r.maxRotationDeg = std::max(r.maxRotationDeg, dr);
        if (dt > params_.reanchor_translation || dr > params_.reanchor_rotation_deg)
            r.moved++;
    }
    if (r.moved > 0)
        for (size_t i = 0; i < contributions_.size(); ++i)
            contributions_[i].T_world_cam = poses[i];
    // One rebuild for both: the final poses, without the points near movers that are
    // unconfirmed or seen through since.
    NearMoverDrops dropped;
    const auto keep = nearMoverFilter(dropped);
    r.unconfirmed = dropped.unconfirmed;
    r.seenThrough = dropped.seenThrough;
    r.onBody = dropped.onBody;
    if (r.moved == 0 && r.discarded == 0 && !keep)
        return r;
    rebuild(keep ? &*keep : nullptr);
    r.rebuilt = true;
    return r;
}

void SemanticMapBuilder::rebuild(const KeepMasks* keep)
{
    pointsMap_.clear();
    octoMap_.clear();
    for (size_t k = 0; k < contributions_.size(); ++k)
        insert(contributions_[k], keep ? &(*keep)[k] : nullptr);
}

std::vector<Eigen::Vector3f> SemanticMapBuilder::moverSamples(
    const maps::BackProjector::Images& images, const core::PinholeCamera& camera)
{
    constexpr int kStep = 4;
    std::vector<Eigen::Vector3f> out;
    if (images.dynamicMask.empty())
        return out;
    for (int v = kStep / 2; v < images.dynamicMask.rows; v += kStep)
    {
        for (int u = kStep / 2; u < images.dynamicMask.cols; u += kStep)
        {
            const float z = images.depth.at<float>(v, u);
            if (images.dynamicMask.at<uint8_t>(v, u) != 0 && z > 0.0F)
                out.push_back(camera.unproject(u, v, z).cast<float>());
        }
    }
    return out;
}

std::function<bool(const Eigen::Vector3f&)> SemanticMapBuilder::nearMovers() const
{
    auto voxels = std::make_shared<MoverVoxels>(params_.prune_near_movers);
    for (const auto& c : contributions_)
        voxels->add(c);
    return [voxels](const Eigen::Vector3f& p) { return voxels->near(p); };
}

size_t SemanticMapBuilder::pruneFreePoints()
{
    if (!params_.points_map || !params_.octomap ||
        (!params_.prune_free_points && !(params_.prune_near_movers > 0.0)))
        return 0;
    const auto carved = [&](const Eigen::Vector3f& p)
    {
        maps::CSemanticOctoMap::Voxel v;
        return octoMap_.voxelAt(p, v) && v.occupancy < 0.5f;
    };
    if (params_.prune_free_points)
        return pointsMap_.removeIf(carved);
    const auto near = nearMovers();
    return pointsMap_.removeIf([&](const Eigen::Vector3f& p) { return near(p) && carved(p); });
}

size_t SemanticMapBuilder::dropUnconfirmedNearMovers()
{
    NearMoverDrops dropped;
    const auto keep = nearMoverFilter(dropped);
    if (keep)
        rebuild(&*keep);
    return dropped.unconfirmed + dropped.seenThrough + dropped.onBody;
}

std::optional<SemanticMapBuilder::KeepMasks> SemanticMapBuilder::nearMoverFilter(
    NearMoverDrops& dropped) const
{
    dropped = {};
    const bool confirm = params_.confirm_near_movers >= 2;
    const bool seeThrough = params_.see_through_margin > 0.0;
    const bool nearTests = (confirm || seeThrough) && params_.prune_near_movers > 0.0;
    const bool bodyTest = params_.movable_body_radius > 0.0;
    if ((!nearTests && !bodyTest) || contributions_.empty())
        return std::nullopt;
    std::vector<std::vector<maps::SemanticPoint>> world;
    world.reserve(contributions_.size());
    for (const auto& c : contributions_)
        world.push_back(toWorld(c));
    const auto drop = dropTest(world, nearTests && confirm, nearTests && seeThrough, bodyTest);
    // Each point's fate once: the rebuild inserts by these masks.
    KeepMasks keep(world.size());
    for (size_t k = 0; k < world.size(); ++k)
    {
        keep[k].assign(world[k].size(), true);
        for (size_t i = 0; i < world[k].size(); ++i)
            keep[k][i] = !drop(world[k][i].position, k, dropped);
    }
    if (dropped.unconfirmed + dropped.seenThrough + dropped.onBody == 0)
        return std::nullopt;
    return keep;
}

std::function<bool(const Eigen::Vector3f&, size_t, SemanticMapBuilder::NearMoverDrops&)>
SemanticMapBuilder::dropTest(const std::vector<std::vector<maps::SemanticPoint>>& world,
                             bool confirm, bool seeThrough, bool bodyTest) const
{
    std::function<bool(const Eigen::Vector3f&)> near;
    if (confirm || seeThrough)
        near = nearMovers();
    std::shared_ptr<const KeyFrameVoxels> voxels;
    if (confirm)
        voxels = confirmationVoxels(world, near);
    std::shared_ptr<const LatestView> latest;
    if (seeThrough)
        latest = std::make_shared<LatestView>(contributions_, params_.see_through_margin,
                                              params_.see_through_majority);
    std::shared_ptr<BodyVoxels> bodies;
    if (bodyTest)
    {
        bodies = std::make_shared<BodyVoxels>(params_.movable_body_radius, params_.confirm_span_s);
        for (const auto& c : contributions_)
            bodies->add(c);
        if (bodies->empty())  // no keyframe saw a movable object
            bodies.reset();
    }
    return [near, voxels, latest, bodies](const Eigen::Vector3f& p, size_t own,
                                          NearMoverDrops& dropped)
    {
        if (bodies && bodies->near(p))
        {
            dropped.onBody++;
            return true;
        }
        const bool nearMover = near && near(p);
        if (nearMover && voxels && !voxels->confirmed(p))
            dropped.unconfirmed++;
        else if (nearMover && latest && latest->seenThrough(p, own))
            dropped.seenThrough++;
        else
            return false;
        return true;
    };
}

std::shared_ptr<const KeyFrameVoxels> SemanticMapBuilder::confirmationVoxels(
    const std::vector<std::vector<maps::SemanticPoint>>& world,
    const std::function<bool(const Eigen::Vector3f&)>& near) const
{
    auto voxels = std::make_shared<KeyFrameVoxels>(
        params_.confirm_radius, static_cast<size_t>(params_.confirm_near_movers),
        params_.confirm_span_s, params_.confirm_clear_distance > 0.0);
    for (size_t k = 0; k < contributions_.size(); ++k)
    {
        const KeyFrameContribution& c = contributions_[k];
        MoverVoxels own(params_.confirm_clear_distance);  // this keyframe's movers alone
        if (params_.confirm_clear_distance > 0.0)
            own.add(c);
        for (const auto& p : world[k])
            if (near(p.position))
                voxels->add(p.position, static_cast<uint32_t>(k), c.timestamp,
                            !own.near(p.position));
    }
    return voxels;
}

size_t SemanticMapBuilder::contributionBytes() const
{
    size_t n = 0;
    for (const auto& c : contributions_)
        n += c.memoryBytes();
    return n;
}
}  // namespace smap::mapping
