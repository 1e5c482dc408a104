// A keyframe: a frame kept in the map with its features, the map points it observes and its
// covisibility edges (keyframes sharing at least N observed points).
// All map objects are guarded by the one Map mutex (Map::mutex()).
#pragma once

#include <Eigen/Geometry>
#include <cstdint>
#include <map>
#include <memory>
#include <vector>

#include "smap/slam/Frame.h"

namespace smap::slam
{
class MapPoint;

class KeyFrame
{
public:
    KeyFrame(uint64_t id, const Frame& frame);

    uint64_t id() const { return id_; }
    uint64_t frameId() const { return frameId_; }
    double timestamp() const { return timestamp_; }

    core::PinholeCamera camera;
    double bf = 0.0;
    double closeDepth = 0.0;
    features::FeatureSet features;
    features::FeatureGrid grid;
    std::vector<float> weights;
    /// Per keypoint (empty: every usable one): shown static, may start a map point (Frame's).
    std::vector<bool> mappable;
    /// Map point per keypoint (null where none). Indices match `features`.
    std::vector<std::shared_ptr<MapPoint>> points;
    cv::Mat thumbnail;

    size_t size() const { return features.size(); }
    bool canMap(size_t i) const { return weights[i] > 0.0F && (mappable.empty() || mappable[i]); }

    Eigen::Isometry3d T_cam_world() const { return T_cam_world_; }
    void setPose(const Eigen::Isometry3d& T_cam_world) { T_cam_world_ = T_cam_world; }
    Eigen::Vector3d centre_world() const { return T_cam_world_.inverse().translation(); }
    /// The part of the map the keyframe belongs to: 0 for the map the run started, a new
    /// number for each re-anchoring (Map::newPart). Keyframes of different parts share no
    /// points until Map::mergePart joins them.
    uint32_t part() const { return part_; }
    void setPart(uint32_t part) { part_ = part; }
    /// The keyframe that started its part (the first of the map, or a re-anchor): bundle
    /// adjustment holds it still, as the frame of its part, and culling keeps it. Merged parts
    /// lose their origin (Map::mergePart).
    bool isPartOrigin() const { return partOrigin_; }
    void setPartOrigin(bool origin) { partOrigin_ = origin; }

    /// Indices of the keypoints that carry a (not bad) map point.
    std::vector<size_t> keypointsWithPoints() const;
    /// Map points observed (not bad) with at least `min_observations` observations.
    int trackedPoints(int min_observations) const;

    /// Recounts shared observations with every other keyframe and keeps edges of weight at
    /// least `min_weight` (the best one always, so the graph stays connected).
    void updateConnections(int min_weight);
    void addConnection(KeyFrame* other, int weight);
    void eraseConnection(KeyFrame* other);
    /// Up to n covisible keyframes, strongest first (n < 0: all).
    std::vector<KeyFrame*> bestCovisibles(int n = -1) const;
    int weight(const KeyFrame* other) const;

    /// Culling: removes the keyframe's observations and edges, and remembers its pose
    /// relative to `parent` so that trajectories through it follow the parent's refinements.
    void setBad(const std::shared_ptr<KeyFrame>& parent);
    bool isBad() const { return bad_; }
    /// Pose of a culled keyframe = T_cam_parent * parent's pose (recursively).
    Eigen::Isometry3d resolvedT_cam_world() const;

private:
    void sortConnections();

    uint64_t id_;
    uint64_t frameId_;
    double timestamp_;
    Eigen::Isometry3d T_cam_world_;
    uint32_t part_ = 0;
    bool partOrigin_ = false;
    std::map<uint64_t, std::pair<KeyFrame*, int>> connections_;
    std::vector<KeyFrame*> ordered_;
    bool bad_ = false;
    std::shared_ptr<KeyFrame> parent_;
    Eigen::Isometry3d T_cam_parent_ = Eigen::Isometry3d::Identity();
};
}  // namespace smap::slam
