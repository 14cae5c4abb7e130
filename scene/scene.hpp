// Analytic, ray-cast test scenes (docs/DESIGN.md §7): the true left, centre and right views of
// one stereo camera, with their exact depths, so that a reprojected eye can be compared with the
// eye the renderer would have drawn.
//
// Conventions. View space: x right, y up, z forward (z is the positive view-space distance of
// docs/DESIGN.md §3). The centre camera sits at the origin. Pixel (i, j) has its centre at
// continuous coordinates (u, v) = (i, j); row 0 is the top row. Pixels are square, so the vertical
// field of view follows from the horizontal one and the aspect ratio.
//
// The stereo camera is the standard stereo projection of docs/DESIGN.md §4: the eye with offset
// sigma (-1/2 left, 0 centre, +1/2 right) shifts clip x by side * S * (clip.w - c), side = 2 sigma.
// In normalised device coordinates that is
//     ndc_x = x / (z tan(fov/2)) + 2 sigma S (1 - c / z),
// which is a camera translated to x = 2 sigma T, T = S c tan(fov/2), whose frustum is sheared by
// the constant 2 sigma S so that the plane z = c projects to the same pixels in every eye.
//
// Files: builders.cpp, what each scene holds and its name; camera.cpp, the eyes' rays and
// projection; trace.cpp, ray casting; texture.cpp, the colour of a surface point; render.cpp,
// whole views (render, visible_in_both, encode_depth).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "reproject/depth.hpp"
#include "reproject/image.hpp"
#include "reproject/parallax.hpp"
#include "reproject/status.hpp"

namespace reproject::scene {

// Signed eye offsets of the three views of a stereo camera (sigma of docs/DESIGN.md §4, from the
// centre).
constexpr double kLeftEye = -0.5;
constexpr double kCentreEye = 0.0;
constexpr double kRightEye = 0.5;
// Default horizontal field of view: 60 degrees, in radians.
constexpr double kDefaultHorizontalFov = 1.0471975511965976;

// Built-in scenes. Add new ones at the end, with a builder in builders.cpp, a name in to_string and
// describe (same file) and an entry in kAllScenes. Every scene stands in the same room shell (a
// tiled floor and a brick back wall that every ray meets) and shares its depth range and
// recommended stereo camera, so that one set of warp flags fits them all; each of the others holds
// one of the default scene's features alone, with the same geometry and texture as in `room`.
enum class SceneId : std::uint8_t {
  room,     // the default: room, boxes, a thin pole, spheres, a near object and an edge object
  boxes,    // the room with boxes at several depths (one of them yawed: slanted faces)
  pole,     // a 2-px-wide pole in front of the textured back wall
  spheres,  // curved depth: a large sphere in the middle distance and the near sphere
  near,     // an object in front of the convergence plane (negative parallax)
  edge,     // a box cut by the left viewport edge, in front of the convergence plane
};
constexpr SceneId kAllScenes[] = {SceneId::room,    SceneId::boxes, SceneId::pole,
                                  SceneId::spheres, SceneId::near,  SceneId::edge};
const char* to_string(SceneId id) noexcept;
bool parse_scene(const char* name, SceneId* out) noexcept;
// One line for help texts: what the scene shows.
const char* describe(SceneId id) noexcept;

struct Vec3 {
  double x = 0.0, y = 0.0, z = 0.0;
};

struct Ray {
  Vec3 origin;
  Vec3 direction;  // direction.z == 1, so the ray parameter of a hit is its view-space depth z
};

// One eye of a stereo camera.
struct Camera {
  int width = 1920;
  int height = 1080;
  double horizontal_fov = kDefaultHorizontalFov;  // radians
  StereoCamera stereo;                         // separation S, convergence c
  double sigma = kCentreEye;                   // eye offset: kLeftEye, kCentreEye, kRightEye

  Camera with_eye(double eye_sigma) const noexcept {
    Camera c = *this;
    c.sigma = eye_sigma;
    return c;
  }
  double tan_half_fov_x() const noexcept;
  double tan_half_fov_y() const noexcept;  // tan_half_fov_x * height / width (square pixels)
  // x of the eye's centre of projection: 2 sigma T with T = StereoCamera::eye_translation(fov).
  double eye_x() const noexcept;
  // The eye's ray through continuous pixel coordinates (u, v).
  Ray ray(double u, double v) const noexcept;
  // Continuous pixel coordinates of a point in front of the eye (p.z > 0): the inverse of ray().
  void project(const Vec3& p, double* u, double* v) const noexcept;
};

// What a ray meets first.
struct Hit {
  double z = 0.0;     // view-space depth (= ray parameter, since direction.z == 1)
  Vec3 point;         // the surface point
  int object = -1;    // index into Scene::objects()
  float rgb[3] = {};  // the surface colour there (view-independent, 0..1)
};

// A rendered view: colour as 3 float planes (R, G, B, 0..1), depth as linear view-space z, and the
// index of the object seen at each pixel (row-major, `width` bytes a row; 255 = none).
struct View {
  Image color;
  Image depth;
  std::vector<std::uint8_t> object;
  int width() const noexcept { return depth.width(); }
  int height() const noexcept { return depth.height(); }
};

class Scene {
 public:
  static Scene make(SceneId id = SceneId::room);

  SceneId id() const noexcept { return id_; }
  const char* name() const noexcept { return to_string(id_); }

  // Every visible surface lies in [min_depth(), max_depth()] (view-space z), for any eye of the
  // recommended camera and any field of view up to 120 degrees.
  double min_depth() const noexcept { return min_depth_; }
  double max_depth() const noexcept { return max_depth_; }
  // Round near/far planes that enclose [min_depth, max_depth] with a margin, for depth encodings.
  double near_plane() const noexcept { return near_; }
  double far_plane() const noexcept { return far_; }
  // A decoder for `encoding` with this scene's near/far (linear and disparity ignore them).
  DepthDecoder decoder(DepthEncoding encoding) const noexcept;

  // Recommended stereo parameters: separation 3 % of the width (S = 0.03) and the convergence
  // plane in the middle of the depth range, measured in inverse depth (the harmonic mean of
  // min_depth and max_depth): parallax is affine in 1/z, so this puts zero parallax halfway
  // between the nearest and the farthest parallax, which are then equal and opposite.
  StereoCamera recommended_stereo() const noexcept;
  // A camera of this scene: the recommended stereo parameters, the given size and eye.
  Camera camera(int width, int height, double sigma = kCentreEye,
                double horizontal_fov = kDefaultHorizontalFov) const noexcept;

  // Object names, e.g. "pole", "edge_box", "near_sphere"; index = Hit::object.
  int object_count() const noexcept { return static_cast<int>(objects_.size()); }
  const char* object_name(int index) const noexcept;
  int find_object(const char* name) const noexcept;  // -1 when absent

  // First surface along the ray (t > 0). False when the ray meets nothing.
  bool trace(const Ray& ray, Hit* hit) const noexcept;

  // Renders one view (one ray through each pixel centre). Rows are split over `threads` threads
  // (0: hardware concurrency); the result does not depend on the thread count.
  Status render(const Camera& camera, View* out, int threads = 0) const;

  // The pixels of `target`'s view that a reprojection from `source`'s view can get right: 1 where
  // the surface point the target pixel sees is also the first surface the source eye sees in its
  // direction, at a source column within [0, source.width - 1]; 0 elsewhere (disocclusions, the
  // strip the source never saw, pixels that see nothing). Decided by tracing in double, not from
  // images: the target's hit point P is projected into the source (same row, column u) and the
  // source ray through (u, row) must meet P itself (same depth to 1e-9 relative). Row-major,
  // `target.width` bytes a row. Both cameras must have the same height.
  Status visible_in_both(const Camera& target, const Camera& source, std::vector<std::uint8_t>* out,
                         int threads = 0) const;

  // Object kinds and materials; public so that the scene builders (builders.cpp) can fill them in.
  enum class Shape : std::uint8_t { plane_y, plane_z, box, sphere, cylinder_y };
  enum class Material : std::uint8_t { floor_tiles, bricks, checker, stripes, bands };
  struct Object {
    std::string name;
    Shape shape = Shape::sphere;
    Material material = Material::checker;
    Vec3 centre;       // plane_y: y is the plane; plane_z: z is the plane; others: the centre
    Vec3 half;         // box: half extents (in its own frame); cylinder_y: half.y = half height
    double radius = 0.0;  // sphere, cylinder_y
    double yaw = 0.0;     // box: rotation about the y axis, radians
    double z_min = -1e300, z_max = 1e300;  // plane_y: the plane's extent in z
    float color_a[3] = {1, 1, 1};
    float color_b[3] = {0, 0, 0};
    double scale = 1.0;  // texture feature size, view-space units
    // Seeds the texture noise. Builders give each object the index it has in the default scene,
    // so that an object looks the same in every scene that holds it.
    std::uint32_t texture_seed = 0;
    // Filled in by add(), to keep them out of the per-ray path: the yaw's cosine and sine, and
    // the squared radius of a sphere around a box (rays that miss it skip the slab test).
    double cos_yaw = 1.0, sin_yaw = 0.0, bound2 = 0.0;
  };
  void add(const Object& object);
  // For builders: the depth range every visible surface lies in, and the near/far planes that
  // enclose it.
  void set_depth_range(double min_depth, double max_depth, double near_plane, double far_plane) noexcept {
    min_depth_ = min_depth;
    max_depth_ = max_depth;
    near_ = near_plane;
    far_ = far_plane;
  }

 private:
  bool intersect(const Object& o, const Ray& ray, double t_max, double* t, Vec3* normal,
                 double uv[2]) const noexcept;
  // Colour from the surface alone (object, normal, texture coordinates): never from the ray.
  void shade(const Object& o, const Vec3& normal, const double uv[2], float rgb[3]) const noexcept;

  SceneId id_ = SceneId::room;
  std::vector<Object> objects_;
  double min_depth_ = 1.0, max_depth_ = 10.0;
  double near_ = 0.5, far_ = 20.0;
  double separation_ = 0.03;
};

// The view's linear depth converted to `decoder`'s encoding with DepthDecoder::encode.
// An empty image when `linear_z` is empty or allocation fails.
Image encode_depth(const Image& linear_z, const DepthDecoder& decoder);

}  // namespace reproject::scene
