#include "pllvo/synth/scene.h"

#include <algorithm>
#include <map>

#include "pllvo/common/error.h"

namespace pllvo::synth {

Eigen::Vector3d Quad::corner(int i) const {
  switch (i & 3) {
    case 0: return origin;
    case 1: return origin + u;
    case 2: return origin + u + v;
    default: return origin + v;
  }
}

double distance_to_quad(const Quad& q, const Eigen::Vector3d& p) {
  // Quads are rectangles (u orthogonal to v), so clamping s and t gives the closest point.
  const Eigen::Vector3d d = p - q.origin;
  const double s = std::clamp(d.dot(q.u) / q.u.squaredNorm(), 0.0, 1.0);
  const double t = std::clamp(d.dot(q.v) / q.v.squaredNorm(), 0.0, 1.0);
  return (p - q.point(s, t)).norm();
}

int SceneBuilder::add_quad(const Quad& quad, Texture texture) {
  if (texture.image.empty() || texture.image.type() != CV_32F)
    throw InternalError("SceneBuilder: texture must be a non-empty CV_32F image");
  if (quad.u.norm() <= 0 || quad.v.norm() <= 0 || std::abs(quad.u.dot(quad.v)) > 1e-9 * quad.area())
    throw InternalError("SceneBuilder: quads must be non-degenerate rectangles");
  const int index = static_cast<int>(scene_.quads.size());
  Quad q = quad;
  q.texture = static_cast<int>(scene_.textures.size());
  for (const auto& e : texture.edges) {
    SceneEdge edge;
    edge.a = q.point(e.a.x(), e.a.y());
    edge.b = q.point(e.b.x(), e.b.y());
    edge.kind = e.kind;
    edge.quads = {index, -1};
    scene_.edges.push_back(edge);
  }
  scene_.quads.push_back(q);
  scene_.textures.push_back(std::move(texture));
  return index;
}

int SceneBuilder::add_facing(const Eigen::Vector3d& centre, const Eigen::Vector3d& normal,
                             const Eigen::Vector3d& up, double width, double height, Texture texture) {
  const Eigen::Vector3d n = normal.normalized();
  const Eigen::Vector3d up_n = (up - up.dot(n) * n).normalized();
  const Eigen::Vector3d right = (-n).cross(up_n);  // viewer looks along -n
  Quad q;
  q.u = right * width;
  q.v = -up_n * height;
  q.origin = centre - 0.5 * q.u - 0.5 * q.v;
  return add_quad(q, std::move(texture));
}

Scene SceneBuilder::finish() {
  // Quad borders: a border shared by two quads (a box's crease) becomes one edge.
  struct Key {
    std::array<long long, 6> c;
    bool operator<(const Key& o) const { return c < o.c; }
  };
  auto quantise = [](const Eigen::Vector3d& p, long long* out) {
    for (int k = 0; k < 3; ++k) out[k] = std::llround(p[k] * 1e5);  // 10 um grid
  };
  std::map<Key, size_t> borders;
  std::vector<SceneEdge> edges;
  for (size_t qi = 0; qi < scene_.quads.size(); ++qi) {
    const auto& q = scene_.quads[qi];
    for (int k = 0; k < 4; ++k) {
      Eigen::Vector3d a = q.corner(k), b = q.corner(k + 1);
      Key key;
      quantise(a, key.c.data());
      quantise(b, key.c.data() + 3);
      if (std::lexicographical_compare(key.c.begin() + 3, key.c.end(), key.c.begin(), key.c.begin() + 3)) {
        std::rotate(key.c.begin(), key.c.begin() + 3, key.c.end());
        std::swap(a, b);
      }
      const auto it = borders.find(key);
      if (it != borders.end()) {
        edges[it->second].quads[1] = static_cast<int>(qi);
        continue;
      }
      SceneEdge e;
      e.a = a;
      e.b = b;
      e.kind = EdgeKind::geometric;
      e.quads = {static_cast<int>(qi), -1};
      borders.emplace(key, edges.size());
      edges.push_back(e);
    }
  }
  for (const auto& e : scene_.edges) edges.push_back(e);
  for (size_t i = 0; i < edges.size(); ++i) edges[i].id = static_cast<int>(i);
  scene_.edges = std::move(edges);
  return std::move(scene_);
}

}  // namespace pllvo::synth
