#pragma once
// The simulated world (issue 4): a textured ground, buildings, trees, poles, people, power-line
// cables, rooms and calibration boards, lit by a sun under drifting cloud shadows. Positions are
// in the local NED frame N (metres; the ground is the plane d = 0, heights are negative d).
// A scene is data: it is read from a JSON file (resources/scenes/*.scene.json, format in the
// docs/vehicle/simulator.md) or built in code by tests, and it knows the exact geometry of everything it renders.
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "uav/world/camera_model.hpp"

namespace uav::world {

// Object ids in rendered id maps: 0 nothing (sky), 1 ground, objects from 2 upwards.
constexpr int kNoObject = 0;
constexpr int kGroundId = 1;

// Ground truth of one obstacle. Cylinders (trees, poles, people) use radius and height; boxes
// (buildings, crates, walls) use size and yaw. `base_N` is the centre of the footprint.
struct Obstacle {
  int id = 0;
  std::string kind;          // building, tree, pole, person, box, cylinder, sphere, wall
  Eigen::Vector3d base_N = Eigen::Vector3d::Zero();
  double radius = 0.0;       // [m] cylinders and trees: trunk or crown radius, whichever is larger
  double height = 0.0;       // [m] above the base
  Eigen::Vector3d size = Eigen::Vector3d::Zero();  // [m] boxes: extent along their own n, e, d
  double yaw = 0.0;          // [rad] boxes: rotation about d
};

// A power-line cable hanging between two attachment points as a catenary (thesis 3.6):
// below the chord by sag_m at mid-span.
struct Cable {
  int id = 0;
  Eigen::Vector3d a_N, b_N;  // attachment points
  double sag_m = 0.0;
  double radius_m = 0.0;
  double catenary_a = 0.0;   // [m] catenary parameter a of z = a cosh(s/a)
  // The curve at the 64 points Distance measures to, a_N first: filled where the scene makes
  // the cable, since the clearance is asked for at every control period and on whole grids.
  std::vector<Eigen::Vector3d> curve_N;
  // Point at fraction s in [0, 1] along the span.
  Eigen::Vector3d PointAt(double s) const;
  // The curve sampled at n points (n >= 2), a_N first.
  std::vector<Eigen::Vector3d> Sample(int n) const;
  // Distance [m] from p_N to the cable's surface (0 inside), along curve_N.
  double Distance(const Eigen::Vector3d& p_N) const;
};

// A chessboard target: cols x rows inner corners, squares of square_m, a white margin of one
// square. Board frame: x along the columns, y along the rows, z the normal; its origin is the
// first inner corner.
struct Chessboard {
  int id = 0;
  int cols = 9;
  int rows = 6;
  double square_m = 0.05;
  Eigen::Isometry3d T_N_board = Eigen::Isometry3d::Identity();
  // Inner corners in the board frame (z = 0), row by row: (c * square, r * square, 0).
  std::vector<Eigen::Vector3d> CornersInBoard() const;
};

struct SunLight {
  Eigen::Vector3d to_sun_N = Eigen::Vector3d(-0.4, -0.4, -0.82).normalized();
  double ambient = 0.35;  // fraction of light that reaches surfaces facing away from the sun
};

// Cloud shadows (thesis Fig. 6.10): a smooth random field drifting with the wind darkens the
// ground where cloud cover exceeds 1 - coverage.
struct CloudShadows {
  bool enabled = false;
  double coverage = 0.3;   // fraction of the ground in shadow
  double darkness = 0.45;  // fraction of light removed in full shadow
  double scale_m = 120.0;  // typical cloud size
  Eigen::Vector2d velocity_NE = Eigen::Vector2d(3.0, 1.0);  // [m/s] drift
};

// How the ground looks.
struct GroundSpec {
  bool enabled = true;
  enum class Layout { kUniform, kFields } layout = Layout::kUniform;
  std::string material = "grass";               // kUniform
  std::vector<std::string> parcel_materials;    // kFields: picked per parcel from the seed
  double parcel_m = 36.0;                       // kFields: parcel size
  double grid_yaw = 0.0;                        // [rad] kFields: orientation of the parcel grid
  int road_every = 4;                           // kFields: a road along every n-th grid line (0: none)
  double road_width_m = 5.0;
};

// A path a moving object follows on the ground (tracking targets, thesis 3.7): it starts at the
// first waypoint at start_s and moves at a constant speed along straight legs; with `loop` it
// goes round the closed polygon, otherwise back and forth. The object turns to face its leg
// (its declared orientation faces the first leg).
struct ObjectPath {
  std::vector<Eigen::Vector2d> waypoints_NE;  // [m] at least two, consecutive ones distinct
  double speed_mps = 1.4;
  double start_s = 0.0;  // [s] on the scene clock (the vehicle's, in the simulator)
  bool loop = true;
};

// Where a moving object is at a time: its footprint centre and heading (yaw about d, from N).
struct ObjectPlacement {
  Eigen::Vector3d base_N = Eigen::Vector3d::Zero();
  double heading_rad = 0.0;
  Eigen::Vector2d velocity_NE = Eigen::Vector2d::Zero();  // [m/s]
};

struct RayHit {
  double t = 0.0;                 // ray parameter: point = origin + t * direction
  Eigen::Vector3d p_N = Eigen::Vector3d::Zero();
  Eigen::Vector3d normal_N = Eigen::Vector3d::Zero();  // unit, facing the ray
  int object_id = kNoObject;
};

class Scene {
 public:
  // An empty world: no ground, no sun shadows, seed 0.
  explicit Scene(uint64_t seed = 0);
  ~Scene();
  Scene(Scene&&) noexcept;
  Scene& operator=(Scene&&) noexcept;

  // Reads a scene file. Throws std::runtime_error naming the file and the JSON path of the first
  // bad entry (unknown type or material, missing field, non-finite or out-of-range value).
  static Scene LoadFile(const std::string& path);
  static Scene Parse(const std::string& json_text, const std::string& source_name);

  uint64_t seed() const;
  const std::string& name() const;
  void SetName(const std::string& name);

  // ---- Building the world (each returns the object id) ------------------------------------
  void SetGround(const GroundSpec& ground);
  void SetSun(const SunLight& sun);
  void SetClouds(const CloudShadows& clouds);
  // false indoors: rays that hit nothing are black, and the simulated GPS receiver, which needs
  // the sky, has no fix.
  void SetSky(bool visible);
  bool sky() const;
  // Box of `size` (n, e, d extents) centred at center_N, rotated by yaw about d. The top face
  // uses `top_material` (roofs) when given.
  int AddBox(const std::string& kind, const Eigen::Vector3d& center_N, const Eigen::Vector3d& size,
             double yaw, const std::string& material, const std::string& top_material = "");
  // Vertical cylinder standing on base_N (its bottom centre), `height` upwards.
  int AddCylinder(const std::string& kind, const Eigen::Vector3d& base_N, double radius,
                  double height, const std::string& material);
  int AddSphere(const std::string& kind, const Eigen::Vector3d& center_N, double radius,
                const std::string& material);
  // Tree: bark trunk and a foliage crown sphere whose top is at `height`.
  int AddTree(const Eigen::Vector3d& base_N, double height, double crown_radius);
  // Person: a body cylinder dressed in `clothing` and a head, `height` tall in total.
  int AddPerson(const Eigen::Vector3d& base_N, double height, const std::string& clothing = "concrete");
  // Room seen from inside: walls and ceiling of a box in `material`, its floor in
  // `floor_material` (the same when empty).
  int AddRoom(const Eigen::Vector3d& center_N, const Eigen::Vector3d& size, const std::string& material,
              const std::string& floor_material = "");
  // Cable between a_N and b_N sagging sag_m at mid-span (catenary).
  int AddCable(const Eigen::Vector3d& a_N, const Eigen::Vector3d& b_N, double sag_m, double radius_m);
  int AddChessboard(int cols, int rows, double square_m, const Eigen::Isometry3d& T_N_board);
  // Makes object `id` (a box, cylinder, sphere or person) move along `path`; from then on its
  // declared position is where it stands before start_s. Throws std::invalid_argument for an
  // unknown id, a cable or board, or a path with fewer than two distinct waypoints, a
  // non-finite value or a speed outside (0, 50] m/s.
  void SetPath(int id, const ObjectPath& path);

  // ---- Ground truth -----------------------------------------------------------------------
  // Obstacles as declared; moving ones are where they stand before their path starts.
  const std::vector<Obstacle>& obstacles() const;
  // Ids of the objects that move, and where each is at time t_s (static objects: as declared).
  std::vector<int> MovingObjects() const;
  ObjectPlacement PlacementAt(int id, double t_s) const;
  const std::vector<Cable>& cables() const;
  // An object or cable said in words for reports ("a wall 2.4 x 0.3 m, 6.2 m high, turned 16
  // deg"); "nothing" for kNoObject or an id the scene does not have.
  std::string Describe(int object_id) const;
  const std::vector<Chessboard>& chessboards() const;
  // Cameras declared by the scene file (defaults when the file has none).
  const std::optional<CameraSetup>& downward_camera() const;
  const std::optional<StereoSetup>& stereo_camera() const;
  // The gimballed camera: T_BC is its mount at zero pitch (looking along the body's x axis); the
  // gimbal keeps it level in roll and pitches it between straight ahead and straight down.
  const std::optional<CameraSetup>& gimbal_camera() const;
  void SetDownwardCamera(const CameraSetup& c);
  void SetGimbalCamera(const CameraSetup& c);
  void SetStereoCamera(const StereoSetup& s);  // the only rig
  // Every stereo rig, in the file's order (the first is stereo_camera()); rig names are unique.
  // AddStereoRig throws std::invalid_argument for a second rig of the same name.
  const std::vector<StereoSetup>& stereo_rigs() const;
  void AddStereoRig(const StereoSetup& s);

  // Nearest surface along origin + t * direction for t in (t_min, t_max), with moving objects
  // where they are at t_s; cables at their true radius. Thread-safe.
  std::optional<RayHit> Intersect(const Eigen::Vector3d& origin_N, const Eigen::Vector3d& direction_N,
                                  double t_min = 1e-6, double t_max = 1e9, double t_s = 0.0) const;

  // Distance [m] from p_N to the nearest surface other than the ground (objects where they are
  // at t_s, cables as their catenaries); 0 inside an object, -1 when the world has none. The
  // avoidance benchmark's and the flight log's true clearance. `nearest_id`, when given, gets
  // the id of the object or cable that surface belongs to (kNoObject when none).
  double Clearance(const Eigen::Vector3d& p_N, double t_s = 0.0, int* nearest_id = nullptr) const;

  // The renderer's view of the scene (implementation detail).
  struct Impl;
  const Impl& impl() const { return *impl_; }

 private:
  std::unique_ptr<Impl> impl_;
};

// Known material names: grass, grass_low, field, soil, gravel, asphalt, roof_tiles, roof_metal,
// brick, plaster, concrete, bark, foliage, plain, dark, and saturated paints and cloth for
// tracking targets: red, blue, yellow, orange.
const std::vector<std::string>& MaterialNames();

}  // namespace uav::world
