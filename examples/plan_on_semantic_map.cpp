// plan_on_semantic_map: a navigator's use of the semantic map. It loads semantic-mapper's
// semantic_map.bin (a CMultiMetricMap; MRPT's class registry knows our maps as soon as the
// program links smap::maps), builds an mrpt::maps::COccupancyGridMap2D of the static obstacles
// in a robot's height band from the semantic octomap (voxels of movable classes, people first,
// left out: they will not be there when the robot comes), plans a path between two free cells
// with mrpt::nav::PlannerSimple2D and writes a PNG of the grid and the path.
//
// The map frame is the first keyframe's camera (optical frame, y down). The floor is found as
// the lowest layer of occupied voxels along the camera's "up" (-y), its plane fitted to give the
// true up. A cell is free where the floor was seen and nothing static stands in the band, an
// obstacle where something static does, unknown (not traversable) elsewhere.
//
// Usage: plan_on_semantic_map SEMANTIC_MAP.bin OUT.png [--maps MAPS.ini] [--band LOW HIGH]
//                             [--robot-radius R]
//   --maps   a CMultiMetricMap declaration (e.g. semantic_maps.ini beside this file): the maps
//            are first made by MRPT's map factory from it, then filled from the file
//   --band   heights above the floor (m) a robot occupies (default 0.15 1.5)
//   --robot-radius  the planner's robot radius (m, default 0.2)
//   --up X Y Z      the up direction in the map frame, and --floor-below H the floor's depth
//                   below the map origin (the first keyframe's camera) along it, when the map
//                   holds too little floor to find them (a hand-held camera that looked at
//                   counters)
//   --unknown-free  cells never observed count as free (optimistic planning)
// Prints the grid, the start and goal, the planning time and whether the path avoids every
// occupied cell (exit code 3 if not, 4 when no path exists).
#include <mrpt/config/CConfigFile.h>
#include <mrpt/img/CImage.h>
#include <mrpt/io/CFileGZInputStream.h>
#include <mrpt/maps/CMultiMetricMap.h>
#include <mrpt/maps/COccupancyGridMap2D.h>
#include <mrpt/nav/planners/PlannerSimple2D.h>
#include <mrpt/serialization/CArchive.h>

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <deque>
#include <exception>
#include <optional>
#include <queue>
#include <stdexcept>
#include <string>
#include <vector>

#include "smap/maps/CSemanticOctoMap.h"
#include "smap/maps/CSemanticPointsMap.h"

namespace
{
struct Options
{
    std::string mapFile, pngFile, mapsIni;
    double bandLow = 0.15, bandHigh = 1.5, robotRadius = 0.2;
    std::optional<Eigen::Vector3f> up;  ///< in the map frame; default: found from the floor
    std::optional<float> floorBelow;    ///< the floor's depth below the map origin along up
    bool unknownFree = false;
};

Options parse(int argc, char** argv)
{
    Options o;
    std::vector<std::string> pos;
    for (int i = 1; i < argc; ++i)
    {
        const std::string a = argv[i];
        auto value = [&]() -> double
        {
            if (i + 1 >= argc)
                throw std::invalid_argument(a + " needs a value");
            return std::stod(argv[++i]);
        };
        if (a == "--maps" && i + 1 < argc)
            o.mapsIni = argv[++i];
        else if (a == "--band")
        {
            o.bandLow = value();
            o.bandHigh = value();
        }
        else if (a == "--robot-radius")
            o.robotRadius = value();
        else if (a == "--up")
        {
            const double x = value(), y = value(), z = value();
            o.up = Eigen::Vector3d(x, y, z).normalized().cast<float>();
        }
        else if (a == "--floor-below")
            o.floorBelow = static_cast<float>(value());
        else if (a == "--unknown-free")
            o.unknownFree = true;
        else
            pos.push_back(a);
    }
    if (pos.size() != 2 || !(o.bandLow < o.bandHigh) || !(o.robotRadius > 0))
        throw std::invalid_argument(
            "usage: plan_on_semantic_map SEMANTIC_MAP.bin OUT.png [--maps MAPS.ini] "
            "[--band LOW HIGH] [--robot-radius R] [--up X Y Z] [--floor-below H] "
            "[--unknown-free]");
    o.mapFile = pos[0];
    o.pngFile = pos[1];
    return o;
}

/// The maps MRPT's factory makes from a CMultiMetricMap declaration (section [map]).
void makeMapsFromIni(const std::string& ini, mrpt::maps::CMultiMetricMap& maps)
{
    mrpt::maps::TSetOfMetricMapInitializers declared;
    declared.loadFromConfigFile(mrpt::config::CConfigFile(ini), "map");
    maps.setListOfMaps(declared);
    std::printf("%s declares:", ini.c_str());
    for (const auto& m : maps.maps)
        std::printf(" %s", m->GetRuntimeClass()->className);
    std::printf("\n");
    if (!maps.mapByClass<smap::maps::CSemanticOctoMap>() ||
        !maps.mapByClass<smap::maps::CSemanticPointsMap>())
        throw std::invalid_argument(ini + " does not declare both semantic maps");
}

void loadMaps(const std::string& file, mrpt::maps::CMultiMetricMap& maps)
{
    mrpt::io::CFileGZInputStream in;
    if (!in.open(file))
        throw std::invalid_argument("cannot open '" + file + "'");
    try
    {
        mrpt::serialization::archiveFrom(in) >> maps;
    }
    catch (const std::exception& e)
    {
        throw std::invalid_argument(
            "'" + file + "' is not a semantic_map.bin: " + std::string(e.what()).substr(0, 200));
    }
}

/// Up (unit, in the map frame) and the floor's height along it: the lowest layer of occupied
/// voxels along the first camera's up, its plane fitted twice.
std::pair<Eigen::Vector3f, float> floorOf(const std::vector<smap::maps::CSemanticOctoMap::Voxel>& v)
{
    Eigen::Vector3f up(0, -1, 0);
    float floor = 0;
    for (int round = 0; round < 3; ++round)
    {
        std::vector<float> h;
        for (const auto& x : v)
            h.push_back(x.centre.dot(up));
        std::nth_element(h.begin(), h.begin() + static_cast<long>(h.size() / 50), h.end());
        floor = h[h.size() / 50];  // 2nd percentile: below it, noise
        Eigen::Vector3f mean = Eigen::Vector3f::Zero();
        std::vector<Eigen::Vector3f> layer;
        for (const auto& x : v)
            if (std::abs(x.centre.dot(up) - floor) < 0.1F)
                layer.push_back(x.centre);
        if (layer.size() < 20)
            break;
        for (const auto& p : layer)
            mean += p / static_cast<float>(layer.size());
        Eigen::Matrix3f cov = Eigen::Matrix3f::Zero();
        for (const auto& p : layer)
            cov += (p - mean) * (p - mean).transpose();
        const Eigen::Vector3f normal =
            Eigen::SelfAdjointEigenSolver<Eigen::Matrix3f>(cov).eigenvectors().col(0);
        if (std::abs(normal.dot(up)) < 0.9F)  // not a floor under the camera: keep the guess
            break;
        up = normal.dot(up) > 0 ? normal : -normal;
        floor = mean.dot(up);
    }
    return {up, floor};
}

enum class Cell : uint8_t
{
    Unknown,
    Free,
    Obstacle,
    Movable  ///< only people (movable classes) there: free for planning, drawn apart
};

struct Grid2D
{
    Eigen::Vector3f up, e1, e2;  ///< the map frame's up and horizontal axes
    float floor = 0;
    float xMin = 0, yMin = 0, res = 0.05F;
    int cols = 0, rows = 0;
    std::vector<Cell> cells;
    Cell& at(int c, int r) { return cells[static_cast<size_t>(r * cols + c)]; }
    Cell at(int c, int r) const { return cells[static_cast<size_t>(r * cols + c)]; }
    double x(int c) const { return xMin + (c + 0.5) * res; }
    double y(int r) const { return yMin + (r + 0.5) * res; }
    int col(double x) const { return static_cast<int>(std::floor((x - xMin) / res)); }
    int row(double y) const { return static_cast<int>(std::floor((y - yMin) / res)); }
};

/// Floor the depth camera missed between floor it saw (a hole of a cell or two, no voxel there):
/// unknown cells with at least 5 of their 8 neighbours free become free, twice over.
void fillFloorHoles(Grid2D& g)
{
    for (int pass = 0; pass < 2; ++pass)
    {
        std::vector<Cell> next = g.cells;
        for (int r = 1; r + 1 < g.rows; ++r)
            for (int c = 1; c + 1 < g.cols; ++c)
            {
                if (g.at(c, r) != Cell::Unknown)
                    continue;
                int free = 0;
                for (int dr = -1; dr <= 1; ++dr)
                    for (int dc = -1; dc <= 1; ++dc)
                        free += (dr != 0 || dc != 0) && g.at(c + dc, r + dr) == Cell::Free ? 1 : 0;
                if (free >= 5)
                    next[static_cast<size_t>(r * g.cols + c)] = Cell::Free;
            }
        g.cells = std::move(next);
    }
}

Grid2D classifyCells(const smap::maps::CSemanticOctoMap& octo, const Options& o)
{
    const auto voxels = octo.occupiedVoxels();
    if (voxels.size() < 100)
        throw std::invalid_argument("the octomap has too few occupied voxels to plan on");
    Grid2D g;
    std::tie(g.up, g.floor) = floorOf(voxels);
    if (o.up)
        g.up = *o.up;
    if (o.floorBelow)
        g.floor = -*o.floorBelow;
    g.e1 = (Eigen::Vector3f::UnitX() - Eigen::Vector3f::UnitX().dot(g.up) * g.up).normalized();
    g.e2 = g.up.cross(g.e1);
    g.res = static_cast<float>(octo.insertionOptions.resolution);
    float xMax = -1e9F, yMax = -1e9F;
    g.xMin = g.yMin = 1e9F;
    for (const auto& v : voxels)
    {
        g.xMin = std::min(g.xMin, v.centre.dot(g.e1));
        xMax = std::max(xMax, v.centre.dot(g.e1));
        g.yMin = std::min(g.yMin, v.centre.dot(g.e2));
        yMax = std::max(yMax, v.centre.dot(g.e2));
    }
    g.xMin -= 0.5F;
    g.yMin -= 0.5F;
    g.cols = static_cast<int>((xMax + 0.5F - g.xMin) / g.res) + 1;
    g.rows = static_cast<int>((yMax + 0.5F - g.yMin) / g.res) + 1;
    g.cells.assign(static_cast<size_t>(g.cols * g.rows), Cell::Unknown);
    const std::vector<bool> movable = octo.labels().movable(0.5);
    // A lone voxel in the band, with nothing above, below or beside it, is depth noise.
    auto supported = [&](const std::vector<uint8_t>& hits, size_t i)
    {
        if (hits[i] == 0)
            return false;
        if (hits[i] >= 2)
            return true;
        const int c = static_cast<int>(i) % g.cols, r = static_cast<int>(i) / g.cols;
        int beside = 0;
        for (int dr = -1; dr <= 1; ++dr)
            for (int dc = -1; dc <= 1; ++dc)
                if ((dr != 0 || dc != 0) && c + dc >= 0 && r + dr >= 0 && c + dc < g.cols &&
                    r + dr < g.rows)
                    beside += hits[static_cast<size_t>((r + dr) * g.cols + c + dc)] > 0 ? 1 : 0;
        return beside >= 2;
    };
    std::vector<uint8_t> floorSeen(g.cells.size(), 0), staticHit(g.cells.size(), 0),
        movableHit(g.cells.size(), 0);
    for (const auto& v : voxels)
    {
        const float h = v.centre.dot(g.up) - g.floor;
        const size_t i =
            static_cast<size_t>(g.row(v.centre.dot(g.e2)) * g.cols + g.col(v.centre.dot(g.e1)));
        const bool isMovable = v.label >= 0 && v.label < static_cast<int>(movable.size()) &&
                               movable[static_cast<size_t>(v.label)];
        if (std::abs(h) <= 0.1F)
            floorSeen[i] = 1;
        else if (h >= o.bandLow && h <= o.bandHigh)
        {
            uint8_t& hits = (isMovable ? movableHit : staticHit)[i];
            hits = static_cast<uint8_t>(std::min(255, hits + 1));
        }
    }
    for (size_t i = 0; i < g.cells.size(); ++i)
        g.cells[i] = supported(staticHit, i)         ? Cell::Obstacle
                     : supported(movableHit, i)      ? Cell::Movable
                     : floorSeen[i] || o.unknownFree ? Cell::Free
                                                     : Cell::Unknown;
    fillFloorHoles(g);
    return g;
}

mrpt::maps::COccupancyGridMap2D toOccupancyGrid(const Grid2D& g)
{
    mrpt::maps::COccupancyGridMap2D grid(g.xMin, g.xMin + g.cols * g.res, g.yMin,
                                         g.yMin + g.rows * g.res, g.res);
    // MRPT's grid cells hold the probability of being free: 1 free, 0 occupied.
    for (int r = 0; r < g.rows; ++r)
        for (int c = 0; c < g.cols; ++c)
        {
            const Cell k = g.at(c, r);
            grid.setCell(c, r, k == Cell::Free || k == Cell::Movable ? 1.0F : 0.0F);
        }
    return grid;
}

bool traversable(const Grid2D& g, int c, int r)
{
    return c >= 0 && r >= 0 && c < g.cols && r < g.rows &&
           (g.at(c, r) == Cell::Free || g.at(c, r) == Cell::Movable);
}

/// Per cell: whether a robot of `radius` centred there touches only traversable cells.
std::vector<bool> clearCells(const Grid2D& g, double radius)
{
    const int reach = static_cast<int>(std::ceil(radius / g.res)) + 1;
    std::vector<bool> clear(g.cells.size(), false);
    for (int r = 0; r < g.rows; ++r)
        for (int c = 0; c < g.cols; ++c)
        {
            bool ok = traversable(g, c, r);
            for (int dr = -reach; ok && dr <= reach; ++dr)
                for (int dc = -reach; ok && dc <= reach; ++dc)
                    if (dr * dr + dc * dc <= reach * reach)
                        ok = traversable(g, c + dc, r + dr);
            clear[static_cast<size_t>(r * g.cols + c)] = ok;
        }
    return clear;
}

/// Clear cells reachable from `start` through clear cells (4-neighbours), farthest first.
std::vector<std::pair<int, int>> reachableFarthestFirst(const Grid2D& g,
                                                        const std::vector<bool>& clear,
                                                        std::pair<int, int> start)
{
    auto free = [&](int c, int r)
    {
        return c >= 0 && r >= 0 && c < g.cols && r < g.rows &&
               clear[static_cast<size_t>(r * g.cols + c)];
    };
    std::vector<int> dist(g.cells.size(), -1);
    std::queue<std::pair<int, int>> q;
    std::vector<std::pair<int, int>> order;
    dist[static_cast<size_t>(start.second * g.cols + start.first)] = 0;
    q.push(start);
    while (!q.empty())
    {
        const auto [c, r] = q.front();
        q.pop();
        order.emplace_back(c, r);
        for (const auto [dc, dr] : {std::pair{1, 0}, {-1, 0}, {0, 1}, {0, -1}})
        {
            const int nc = c + dc, nr = r + dr;
            if (free(nc, nr) && dist[static_cast<size_t>(nr * g.cols + nc)] < 0)
            {
                dist[static_cast<size_t>(nr * g.cols + nc)] =
                    dist[static_cast<size_t>(r * g.cols + c)] + 1;
                q.emplace(nc, nr);
            }
        }
    }
    std::reverse(order.begin(), order.end());
    return order;
}

/// The clear cell nearest to a point of the plane within the largest region of clear cells
/// (4-neighbours): where the robot can go farthest.
std::pair<int, int> startCell(const Grid2D& g, const std::vector<bool>& clear, double x, double y)
{
    std::vector<int> region(g.cells.size(), -1);
    std::vector<size_t> sizes;
    for (size_t i = 0; i < g.cells.size(); ++i)
    {
        if (!clear[i] || region[i] >= 0)
            continue;
        const int id = static_cast<int>(sizes.size());
        const auto cells = reachableFarthestFirst(
            g, clear, {static_cast<int>(i) % g.cols, static_cast<int>(i) / g.cols});
        for (const auto& [c, r] : cells)
            region[static_cast<size_t>(r * g.cols + c)] = id;
        sizes.push_back(cells.size());
    }
    if (sizes.empty())
        throw std::invalid_argument(
            "no free cell clear of obstacles by the robot radius: the floor was never seen");
    const int largest =
        static_cast<int>(std::max_element(sizes.begin(), sizes.end()) - sizes.begin());
    std::pair<int, int> best{-1, -1};
    double bestD = 1e18;
    for (int r = 0; r < g.rows; ++r)
        for (int c = 0; c < g.cols; ++c)
            if (region[static_cast<size_t>(r * g.cols + c)] == largest)
            {
                const double d = std::hypot(g.x(c) - x, g.y(r) - y);
                if (d < bestD)
                {
                    bestD = d;
                    best = {c, r};
                }
            }
    return best;
}

/// Cells the path crosses (its points and its straight segments, sampled at a quarter cell)
/// that hold a static obstacle.
int obstaclesOnPath(const Grid2D& g, const std::deque<mrpt::math::TPoint2D>& path)
{
    int hits = 0;
    for (size_t i = 0; i + 1 < path.size(); ++i)
    {
        const double len = std::hypot(path[i + 1].x - path[i].x, path[i + 1].y - path[i].y);
        const int steps = std::max(1, static_cast<int>(len / (g.res / 4)));
        for (int s = 0; s <= steps; ++s)
        {
            const double t = static_cast<double>(s) / steps;
            const int c = g.col(path[i].x + t * (path[i + 1].x - path[i].x));
            const int r = g.row(path[i].y + t * (path[i + 1].y - path[i].y));
            if (c >= 0 && r >= 0 && c < g.cols && r < g.rows && g.at(c, r) == Cell::Obstacle)
                hits++;
        }
    }
    return hits;
}

void writePng(const Grid2D& g, const std::deque<mrpt::math::TPoint2D>& path,
              std::pair<int, int> start, std::pair<int, int> goal, const std::string& file)
{
    constexpr int kScale = 4;
    mrpt::img::CImage img(g.cols * kScale, g.rows * kScale, mrpt::img::CH_RGB);
    auto px = [&](double x) { return static_cast<int>((x - g.xMin) / g.res * kScale); };
    auto py = [&](double y)
    { return (g.rows * kScale - 1) - static_cast<int>((y - g.yMin) / g.res * kScale); };
    for (int r = 0; r < g.rows; ++r)
        for (int c = 0; c < g.cols; ++c)
        {
            const Cell k = g.at(c, r);
            const mrpt::img::TColor colour = k == Cell::Free ? mrpt::img::TColor(255, 255, 255)
                                             : k == Cell::Obstacle ? mrpt::img::TColor(0, 0, 0)
                                             : k == Cell::Movable
                                                 ? mrpt::img::TColor(255, 170, 170)
                                                 : mrpt::img::TColor(160, 160, 160);
            const int x0 = c * kScale, y0 = (g.rows - 1 - r) * kScale;
            img.filledRectangle(x0, y0, x0 + kScale - 1, y0 + kScale - 1, colour);
        }
    for (size_t i = 0; i + 1 < path.size(); ++i)
        img.line(px(path[i].x), py(path[i].y), px(path[i + 1].x), py(path[i + 1].y),
                 mrpt::img::TColor(0, 90, 255), 3);
    img.drawCircle(px(g.x(start.first)), py(g.y(start.second)), 3 * kScale,
                   mrpt::img::TColor(0, 180, 0), 3);
    img.drawCircle(px(g.x(goal.first)), py(g.y(goal.second)), 3 * kScale,
                   mrpt::img::TColor(220, 0, 0), 3);
    if (!img.saveToFile(file))
        throw std::runtime_error("cannot write '" + file + "'");
}

int run(const Options& o)
{
    mrpt::maps::CMultiMetricMap maps;
    if (!o.mapsIni.empty())
        makeMapsFromIni(o.mapsIni, maps);
    loadMaps(o.mapFile, maps);
    const auto octo = maps.mapByClass<smap::maps::CSemanticOctoMap>();
    if (!octo)
        throw std::invalid_argument("'" + o.mapFile + "' holds no CSemanticOctoMap");
    const auto tGrid = std::chrono::steady_clock::now();
    const Grid2D g = classifyCells(*octo, o);
    const auto count = [&](Cell k) { return std::count(g.cells.begin(), g.cells.end(), k); };
    std::printf(
        "grid %d x %d cells of %.2f m: %ld free, %ld static obstacles, %ld only people "
        "(left out), %ld unknown; floor %.2f m below the first camera\n",
        g.cols, g.rows, g.res, count(Cell::Free), count(Cell::Obstacle), count(Cell::Movable),
        count(Cell::Unknown), -g.floor);
    const auto grid = toOccupancyGrid(g);
    std::printf("grid built in %.1f ms\n",
                std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - tGrid)
                    .count());
    // Start: the cell nearest to where the first camera stood in the largest region a robot fits
    // in; goal: the farthest cell reachable from it for which the planner finds a path.
    const std::vector<bool> clear = clearCells(g, o.robotRadius);
    const auto start = startCell(g, clear, 0.0, 0.0);
    mrpt::nav::PlannerSimple2D planner;
    planner.robotRadius = static_cast<float>(o.robotRadius);
    planner.minStepInReturnedPath = 0.1F;
    const auto t0 = std::chrono::steady_clock::now();
    std::deque<mrpt::math::TPoint2D> path;
    std::pair<int, int> goal{-1, -1};
    int tries = 0;
    for (const auto& cell : reachableFarthestFirst(g, clear, start))
    {
        if (++tries > 20)
            break;
        bool notFound = true;
        planner.computePath(grid, {g.x(start.first), g.y(start.second), 0},
                            {g.x(cell.first), g.y(cell.second), 0}, path, notFound);
        if (!notFound && path.size() > 1)
        {
            goal = cell;
            break;
        }
        path.clear();
    }
    const double ms =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    if (goal.first < 0)
    {
        std::printf("no path found from the start cell (%d tries, %.1f ms)\n", tries - 1, ms);
        writePng(g, path, start, start, o.pngFile);
        std::printf("wrote %s (the grid only)\n", o.pngFile.c_str());
        return 4;
    }
    double length = 0;
    for (size_t i = 0; i + 1 < path.size(); ++i)
        length += std::hypot(path[i + 1].x - path[i].x, path[i + 1].y - path[i].y);
    const int hits = obstaclesOnPath(g, path);
    std::printf(
        "path from (%.2f, %.2f) to (%.2f, %.2f): %zu waypoints, %.2f m; planning took "
        "%.1f ms (%d planner runs)\n",
        g.x(start.first), g.y(start.second), g.x(goal.first), g.y(goal.second), path.size(), length,
        ms, tries);
    std::printf("path avoids every occupied cell: %s\n", hits == 0 ? "yes" : "NO");
    writePng(g, path, start, goal, o.pngFile);
    std::printf("wrote %s\n", o.pngFile.c_str());
    return hits == 0 ? 0 : 3;
}
}  // namespace

int main(int argc, char** argv)
{
    try
    {
        return run(parse(argc, argv));
    }
    catch (const std::invalid_argument& e)
    {
        std::fprintf(stderr, "plan_on_semantic_map: %s\n", e.what());
        return 2;
    }
    catch (const std::exception& e)
    {
        std::fprintf(stderr, "plan_on_semantic_map: internal error: %s\n", e.what());
        return 1;
    }
}
