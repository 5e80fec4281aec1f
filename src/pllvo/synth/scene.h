#pragma once
// A synthetic scene as plain data: textured planar quads, the exact straight 3-D edges
// they make (quad borders and the edges drawn in their textures), lights and the free
// space the camera may fly in. World frame: z up, metres.
#include <array>
#include <cstdint>
#include <vector>

#include <Eigen/Geometry>
#include <opencv2/core.hpp>

namespace pllvo::synth {

enum class EdgeKind : uint8_t {
  geometric = 0,     ///< border of a quad: a crease, silhouette or depth step
  texture_step = 1,  ///< a step edge drawn in a texture (poster shapes, book spines, tape)
  texture_line = 2,  ///< a thin line drawn in a texture (tile grout, ceiling grid); the segment is its centre
};

/// A straight edge of a texture in normalised texture coordinates (s, t in [0, 1]).
struct TextureEdge {
  Eigen::Vector2d a, b;
  EdgeKind kind = EdgeKind::texture_step;
};

/// Reflectance (or, for emissive surfaces, emitted radiance) of one quad, CV_32F, with the
/// texture edges drawn in it. Column s*cols, row t*rows; texel centres at +0.5.
struct Texture {
  cv::Mat image;
  std::vector<TextureEdge> edges;
  bool emissive = false;
  /// Emissive surfaces: radiance multiplier per lighting state (0: lights on, 1: lights off);
  /// a negative value makes the surface reflect light like any other in that state (a lamp
  /// switched off).
  std::array<double, 2> emission = {1.0, 1.0};
};

/// Parallelogram origin + s*u + t*v, s, t in [0, 1]. Seen from its front side, u points
/// right and v down (so the front normal is v x u, pointing at the viewer).
struct Quad {
  Eigen::Vector3d origin = Eigen::Vector3d::Zero();
  Eigen::Vector3d u = Eigen::Vector3d::UnitX();
  Eigen::Vector3d v = Eigen::Vector3d::UnitY();
  int texture = -1;
  bool two_sided = false;

  Eigen::Vector3d corner(int i) const;  ///< 0: origin, 1: +u, 2: +u+v, 3: +v
  Eigen::Vector3d normal() const { return v.cross(u).normalized(); }
  Eigen::Vector3d point(double s, double t) const { return origin + s * u + t * v; }
  bool faces(const Eigen::Vector3d& eye) const { return two_sided || normal().dot(eye - origin) > 0; }
  double area() const { return u.cross(v).norm(); }
};

/// A straight 3-D edge with a stable id (the same in every frame).
struct SceneEdge {
  int id = 0;
  Eigen::Vector3d a, b;
  EdgeKind kind = EdgeKind::geometric;
  /// The quads the edge lies on (a crease has two, a texture edge one; -1 when unused).
  std::array<int, 2> quads = {-1, -1};
};

/// Point light; `direction` non-zero makes it a cosine emitter (ceiling panel, window).
struct Light {
  Eigen::Vector3d position = Eigen::Vector3d::Zero();
  Eigen::Vector3d direction = Eigen::Vector3d::Zero();
  double power = 1.0;
  std::array<bool, 2> on = {true, true};  ///< per lighting state (0: lights on, 1: lights off)
};

struct Box3 {
  Eigen::Vector3d min = Eigen::Vector3d::Zero(), max = Eigen::Vector3d::Zero();
  bool contains(const Eigen::Vector3d& p, double eps = 0) const {
    return (p.array() >= min.array() - eps).all() && (p.array() <= max.array() + eps).all();
  }
};

struct Scene {
  std::vector<Quad> quads;
  std::vector<Texture> textures;  ///< one per quad (quads[i].texture indexes it)
  std::vector<SceneEdge> edges;   ///< ids are indices
  std::vector<Light> lights;
  std::array<double, 2> ambient = {0.15, 0.02};  ///< irradiance without lights, per state
  /// Where the camera may be: every point inside keeps `clearance` to all surfaces.
  Box3 free_space;
  /// Yaw (rad) the camera should face on average (corridors: along the axis).
  double preferred_yaw = 0;
  bool has_preferred_yaw = false;
};

/// Distance from a point to a quad (the closest point of the parallelogram).
double distance_to_quad(const Quad& q, const Eigen::Vector3d& p);

/// Builds scenes from quads and textures: converts texture edges to 3-D edges, adds the
/// quad borders and merges borders shared by two quads into one crease.
class SceneBuilder {
 public:
  /// Adds a quad with its own texture; returns its index.
  int add_quad(const Quad& quad, Texture texture);
  /// A quad whose front faces direction `normal`, centred at `centre`, `up` giving the
  /// texture's up direction (u = right, v = down as seen from the front).
  int add_facing(const Eigen::Vector3d& centre, const Eigen::Vector3d& normal,
                 const Eigen::Vector3d& up, double width, double height, Texture texture);
  void add_light(const Light& light) { scene_.lights.push_back(light); }
  Scene& scene() { return scene_; }
  /// Finishes the edge list (ids are indices afterwards) and returns the scene.
  Scene finish();

 private:
  Scene scene_;
};

}  // namespace pllvo::synth
