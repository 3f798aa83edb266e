// SPDX-License-Identifier: MIT
// cifs Python bindings — cifs.render: cameras, images and their OpenEXR / PNG files, the rasterisers,
// the chaos-game density of a CIFS and the classic point IFS (docs/rendering.md).
#include <climits>
#include <cstdint>
#include <cstring>
#include <functional>
#include <string>
#include <utility>

#include "arrays.hpp"
#include "bindings.hpp"
#include "cifs/errors.hpp"
#include "cifs/render/camera.hpp"
#include "cifs/render/chaos_density.hpp"
#include "cifs/render/image.hpp"
#include "cifs/render/png.hpp"
#include "cifs/render/point_ifs.hpp"
#include "cifs/render/preview.hpp"
#include "cifs/render/progress.hpp"
#include "cifs/render/raster.hpp"

namespace cifs::python {
namespace {

using namespace cifs::render;

/// Exactly three numbers (a 3-vector or a colour).
std::array<double, 3> three(const py::handle& object, const std::string& where) {
  const py::array a = numeric(object, where, "iuf");
  if (a.ndim() != 1 || a.size() != 3)
    throw InvalidInput(where + ": expected 3 numbers, got shape " + shape_text(a));
  const auto d = DoubleArray::ensure(a);
  return {d.data()[0], d.data()[1], d.data()[2]};
}

Eigen::Vector3d vec3(const py::handle& object, const std::string& where) {
  const auto v = three(object, where);
  return {v[0], v[1], v[2]};
}

py::tuple tuple3(const Eigen::Vector3d& v) {
  return py::make_tuple(v[0], v[1], v[2]);
}
py::tuple tuple3(const std::array<double, 3>& v) {
  return py::make_tuple(v[0], v[1], v[2]);
}

/// 8-bit sRGB colours `(k, 3)` with values in 0 … 255.
std::vector<Rgb8> rgb8_rows(const py::handle& object, const std::string& where) {
  const py::array a = numeric(object, where, "iu");
  if (a.ndim() != 2 || a.shape(1) != 3)
    throw InvalidInput(where + ": expected an integer array of shape (k, 3), got shape " + shape_text(a));
  const Int64s ints = Int64s::ensure(a);  // the converted copy must outlive the proxy reading it
  const auto v = ints.unchecked<2>();
  std::vector<Rgb8> rows(static_cast<std::size_t>(v.shape(0)));
  for (py::ssize_t i = 0; i < v.shape(0); ++i)
    for (py::ssize_t j = 0; j < 3; ++j) {
      if (v(i, j) < 0 || v(i, j) > 255)
        throw InvalidInput(where + "[" + std::to_string(i) + "][" + std::to_string(j) +
                           "] = " + std::to_string(v(i, j)) + " is outside 0 … 255");
      rows[static_cast<std::size_t>(i)][static_cast<std::size_t>(j)] = static_cast<std::uint8_t>(v(i, j));
    }
  return rows;
}

Rgb8 rgb8(const py::handle& object, const std::string& where) {
  py::array a = numeric(object, where, "iu");
  if (a.ndim() != 1 || a.size() != 3)
    throw InvalidInput(where + ": expected 3 integers, got shape " + shape_text(a));
  return rgb8_rows(a.reshape({1, 3}), where)[0];
}

py::list rgb8_list(const std::vector<Rgb8>& rows) {
  py::list out;
  for (const Rgb8& c : rows) out.append(py::make_tuple(c[0], c[1], c[2]));
  return out;
}

unsigned threads_arg(std::int64_t value, const std::string& where) {
  if (value < 0 || value > std::int64_t{UINT_MAX})
    throw InvalidInput(where + " = " + std::to_string(value) + " is outside 0 … " + std::to_string(UINT_MAX));
  return static_cast<unsigned>(value);
}

/// Copies `values` (`height·width`, row-major) into a `(height, width)` array.
template <typename T>
py::array_t<T> grid(const std::vector<T>& values, std::size_t width, std::size_t height,
                    const std::string& what) {
  if (values.size() != width * height)
    throw InvalidInput(what + " holds " + std::to_string(values.size()) + " values, expected " +
                       std::to_string(width * height));
  py::array_t<T> out({static_cast<py::ssize_t>(height), static_cast<py::ssize_t>(width)});
  if (!values.empty()) std::memcpy(out.mutable_data(), values.data(), sizeof(T) * values.size());
  return out;
}

/// A `(height, width)` array of the image's size (any real dtype) as `height·width` values.
template <typename T>
std::vector<T> grid_values(const Image& image, const py::handle& object, const std::string& where,
                           const char* kinds) {
  const py::array a = numeric(object, where, kinds);
  if (a.ndim() != 2 || a.shape(0) != static_cast<py::ssize_t>(image.height) ||
      a.shape(1) != static_cast<py::ssize_t>(image.width))
    throw InvalidInput(where + ": shape " + shape_text(a) + ", expected (height, width) = (" +
                       std::to_string(image.height) + ", " + std::to_string(image.width) + ")");
  const auto c = py::array_t<T, py::array::c_style | py::array::forcecast>::ensure(a);
  return std::vector<T>(c.data(), c.data() + c.size());
}

void set_channel(Image& image, const std::string& name, const py::handle& values) {
  const std::string where = "set_channel: channels[\"" + name + "\"]";
  if (name.empty()) throw InvalidInput("set_channel: a channel has an empty name");
  if (name == "state")
    throw InvalidInput(where + ": the name is reserved for the UINT state channel (Image.state)");
  image.channels[name] = grid_values<float>(image, values, where, "iuf");
}

const std::vector<float>& channel(const Image& image, const std::string& name) {
  const auto it = image.channels.find(name);
  if (it == image.channels.end()) throw InvalidInput("channels: the image has no channel " + name);
  return it->second;
}

std::string image_repr(const Image& image) {
  std::string names;
  for (const auto& [name, values] : image.channels) names += (names.empty() ? "" : " ") + name;
  return "Image(" + std::to_string(image.width) + " by " + std::to_string(image.height) + ", channels [" +
         names + "]" + (image.state ? ", state" : "") + ")";
}

/// The dict-like view of Image::channels.
struct ImageChannels {
  Image* image;
};

PreviewOptions preview_options(PreviewMode mode, double max_density, double gamma, const py::handle& ramp,
                               const py::handle& background, double exposure, const std::string& who) {
  PreviewOptions o;
  o.mode = mode;
  o.tone.max_density = max_density;
  o.tone.gamma = gamma;
  o.tone.ramp = rgb8_rows(ramp, who + ": ramp");
  o.background = rgb8(background, who + ": background");
  o.exposure = exposure;
  return o;
}

/// Interleaved rows of 3|4 bytes as `(height, width, channels)`.
py::array_t<std::uint8_t> pixel_array(const std::vector<std::uint8_t>& pixels, std::size_t width,
                                      std::size_t height, std::size_t channels) {
  py::array_t<std::uint8_t> out({static_cast<py::ssize_t>(height), static_cast<py::ssize_t>(width),
                                 static_cast<py::ssize_t>(channels)});
  if (!pixels.empty()) std::memcpy(out.mutable_data(), pixels.data(), pixels.size());
  return out;
}

std::string bounds_repr(const Bounds& b) {
  return "Bounds(x_min=" + std::string(py::repr(py::float_(b.x_min))) +
         ", x_max=" + std::string(py::repr(py::float_(b.x_max))) +
         ", y_min=" + std::string(py::repr(py::float_(b.y_min))) +
         ", y_max=" + std::string(py::repr(py::float_(b.y_max))) + ")";
}

/// pybind11's enum_ gives `value` no docstring: it is redefined with one.
template <typename E>
int enum_value(E e) {
  return static_cast<int>(e);
}

constexpr const char* kRampDoc = "colour stops `(k, 3)` (8-bit sRGB, k ≥ 1) spread evenly over [0, 1]";

/// Cameras.
void bind_camera_type(py::module_& m) {
  py::enum_<Projection>(m, "Projection", "Camera projection.")
      .value("orthographic", Projection::orthographic, "Parallel projection (Camera.ortho_height).")
      .value("perspective", Projection::perspective, "Pinhole projection (Camera.fov_y, Camera.near).")
      .def_property_readonly("value", &enum_value<Projection>, "The integer value.");

  const Camera c{};
  py::class_<Camera>(m, "Camera", R"(A pinhole or orthographic camera looking from `eye` towards `target`.

Pixel coordinates: x to the right, y down, pixel (i, j) covers [i, i+1) × [j, j+1). Depth is
(p − eye)·f with f the unit viewing direction. Fields are checked when the camera is used
(view_transform, the renderers): InvalidInput for a zero image size, eye = target, `up` parallel to
the view, fov_y outside (0, 180), ortho_height ≤ 0 or near ≤ 0.)")
      .def(py::init([](Projection projection, const py::object& eye, const py::object& target,
                       const py::object& up, double fov_y, double ortho_height, double near,
                       std::int64_t width, std::int64_t height) {
             Camera camera;
             camera.projection = projection;
             camera.eye = vec3(eye, "camera: eye");
             camera.target = vec3(target, "camera: target");
             camera.up = vec3(up, "camera: up");
             camera.fov_y = fov_y;
             camera.ortho_height = ortho_height;
             camera.near = near;
             camera.width = count_arg(width, "camera: width");
             camera.height = count_arg(height, "camera: height");
             return camera;
           }),
           py::kw_only(), py::arg("projection") = c.projection, py::arg("eye") = tuple3(c.eye),
           py::arg("target") = tuple3(c.target), py::arg("up") = tuple3(c.up), py::arg("fov_y") = c.fov_y,
           py::arg("ortho_height") = c.ortho_height, py::arg("near") = c.near, py::arg("width") = c.width,
           py::arg("height") = c.height,
           R"(A camera from keyword arguments (the C++ Camera's fields and defaults).

eye, target, up: 3 numbers each; fov_y: vertical field of view in degrees (perspective);
ortho_height: visible height in world units (orthographic); near: smallest visible depth
(perspective); width, height: image size in pixels. Raises InvalidInput for vectors that are not
3 numbers or negative sizes.)")
      .def_readwrite("projection", &Camera::projection, "Projection.orthographic or Projection.perspective.")
      .def_property(
          "eye", [](const Camera& cam) { return cam.eye; },
          [](Camera& cam, const py::object& v) { cam.eye = vec3(v, "camera: eye"); },
          "Position of the eye: float64 array (3,) (a copy; assign a whole vector to change it).")
      .def_property(
          "target", [](const Camera& cam) { return cam.target; },
          [](Camera& cam, const py::object& v) { cam.target = vec3(v, "camera: target"); },
          "Point looked at: float64 array (3,) (a copy).")
      .def_property(
          "up", [](const Camera& cam) { return cam.up; },
          [](Camera& cam, const py::object& v) { cam.up = vec3(v, "camera: up"); },
          "Upward direction of the image, not parallel to the view: float64 array (3,) (a copy).")
      .def_readwrite("fov_y", &Camera::fov_y, "Perspective: vertical field of view in degrees, in (0, 180).")
      .def_readwrite("ortho_height", &Camera::ortho_height, "Orthographic: visible height in world units.")
      .def_readwrite("near", &Camera::near, "Perspective: smallest visible depth (> 0).")
      .def_property(
          "width", [](const Camera& cam) { return cam.width; },
          [](Camera& cam, std::int64_t v) { cam.width = count_arg(v, "camera: width"); },
          "Image width in pixels.")
      .def_property(
          "height", [](const Camera& cam) { return cam.height; },
          [](Camera& cam, std::int64_t v) { cam.height = count_arg(v, "camera: height"); },
          "Image height in pixels.")
      .def("__repr__", [](const Camera& cam) {
        const auto v = [](const Eigen::Vector3d& p) { return std::string(py::repr(tuple3(p))); };
        return std::string("Camera(") +
               (cam.projection == Projection::perspective
                    ? "perspective, fov_y=" + std::to_string(cam.fov_y)
                    : "orthographic, ortho_height=" + std::string(py::repr(py::float_(cam.ortho_height)))) +
               ", eye=" + v(cam.eye) + ", target=" + v(cam.target) + ", " + std::to_string(cam.width) +
               " by " + std::to_string(cam.height) + ")";
      });
}

/// Projection and framing.
void bind_camera_projection(py::module_& m) {
  py::class_<Projected>(m, "Projected", "A projected point: pixel coordinates x (right), y (down) and depth.")
      .def_readonly("x", &Projected::x, "Pixel x coordinate (to the right).")
      .def_readonly("y", &Projected::y, "Pixel y coordinate (down).")
      .def_readonly("depth", &Projected::depth, "Depth (p − eye)·f along the viewing direction.")
      .def("__repr__", [](const Projected& p) {
        return "Projected(x=" + std::string(py::repr(py::float_(p.x))) +
               ", y=" + std::string(py::repr(py::float_(p.y))) +
               ", depth=" + std::string(py::repr(py::float_(p.depth))) + ")";
      });

  py::class_<ViewTransform>(
      m, "ViewTransform", "A validated camera as the rasterisers use it: orthonormal basis and pixel scale.")
      .def_property_readonly(
          "eye", [](const ViewTransform& v) { return v.eye; }, "Eye position, float64 (3,).")
      .def_property_readonly(
          "right", [](const ViewTransform& v) { return v.right; },
          "Unit right vector r = f × up/|f × up|, (3,).")
      .def_property_readonly(
          "up", [](const ViewTransform& v) { return v.up; }, "Unit up vector u = r × f, (3,).")
      .def_property_readonly(
          "forward", [](const ViewTransform& v) { return v.forward; }, "Unit viewing direction f, (3,).")
      .def_readonly("perspective", &ViewTransform::perspective, "Whether the projection is perspective.")
      .def_readonly("scale", &ViewTransform::scale,
                    "Pixels per world unit (orthographic) or focal length F in pixels (perspective).")
      .def_readonly("cx", &ViewTransform::cx, "Image centre x (width/2).")
      .def_readonly("cy", &ViewTransform::cy, "Image centre y (height/2).")
      .def_readonly("near", &ViewTransform::near, "Smallest visible depth (perspective).")
      .def(
          "project",
          [](const ViewTransform& v, const py::object& point) {
            return v.project(vec3(point, "project: point"));
          },
          py::arg("point"),
          "Pixel coordinates and depth of a world point (3 numbers), without clipping (see "
          "visible_depth).\n\n"
          "Raises InvalidInput when the point is not 3 numbers.")
      .def("visible_depth", &ViewTransform::visible_depth, py::arg("depth"),
           "Whether a depth is in front of the camera (always True for orthographic cameras).")
      .def("__repr__", [](const ViewTransform& v) {
        return std::string("ViewTransform(") + (v.perspective ? "perspective" : "orthographic") +
               ", scale=" + std::string(py::repr(py::float_(v.scale))) + ")";
      });

  m.def("view_transform", &view_transform, py::arg("camera"),
        "Validates `camera` and returns its ViewTransform.\n\n"
        "Raises InvalidInput for a zero image size (or a side above 65536), non-finite vectors, eye = "
        "target, up\n"
        "parallel to the view direction, fov_y outside (0, 180), ortho_height ≤ 0 or near ≤ 0.");
  m.def(
      "project",
      [](const Camera& camera, const py::object& point) {
        return project(camera, vec3(point, "project: point"));
      },
      py::arg("camera"), py::arg("point"),
      "Projects a world point (3 numbers) with `camera` (validated on every call: prefer view_transform in\n"
      "loops). Returns Projected. Raises InvalidInput for an invalid camera or point.");

  const FramingOptions f{};
  m.def(
      "frame",
      [](const py::object& points, std::int64_t width, std::int64_t height, double margin, bool perspective,
         const py::object& view_direction, const py::object& up, double fov_y, bool tight) {
        FramingOptions o;
        o.width = count_arg(width, "frame: width");
        o.height = count_arg(height, "frame: height");
        o.margin = margin;
        o.perspective = perspective;
        if (!view_direction.is_none()) o.view_direction = vec3(view_direction, "frame: view_direction");
        o.up = vec3(up, "frame: up");
        o.fov_y = fov_y;
        o.tight = tight;
        return frame(points_from(points, "frame: points"), o);
      },
      py::arg("points"), py::kw_only(), py::arg("width") = f.width, py::arg("height") = f.height,
      py::arg("margin") = f.margin, py::arg("perspective").noconvert() = f.perspective,
      py::arg("view_direction") = py::none(), py::arg("up") = tuple3(f.up), py::arg("fov_y") = f.fov_y,
      py::arg("tight").noconvert() = f.tight,
      R"(A Camera that shows all of `points` (float64 (n, 2|3)) with a margin.

Planar shapes (2 columns, or every z equal) get an orthographic top view (x right, y up) whose
bounding box is centred and fills the image up to `margin` (fraction of the image per side) in its
tighter direction. Other shapes are seen along `view_direction` (from the centre towards the eye,
`up` the world's up; None: (1, −1.6, 1.1) turned about `up` to the side where the points spread widest,
C++ automatic_view_direction), in perspective (fov_y degrees) or orthographic: with `tight` the points'
projection, centred, fills the image up to `margin` in its tighter direction; without it (the
former framing) their bounding sphere fits.
Raises InvalidInput for no points, non-finite points, a column count other than 2 or 3, a margin
outside [0, 0.45] or a zero image size.)");
}

void bind_camera(py::module_& m) {
  bind_camera_type(m);
  bind_camera_projection(m);
}

/// The channels of an image.
void bind_image_channels(py::module_& m) {
  py::class_<ImageChannels>(m, "ImageChannels",
                            "The float channels of an Image by name, dict-like: each value is a float32 copy "
                            "of shape (height, width).")
      .def(
          "__getitem__",
          [](const ImageChannels& c, const std::string& name) {
            return read_only(
                grid(channel(*c.image, name), c.image->width, c.image->height, "channels[\"" + name + "\"]"));
          },
          py::arg("name"),
          "The channel `name` as float32 (height, width) (a read-only copy); InvalidInput if missing.")
      .def(
          "__setitem__",
          [](ImageChannels& c, const std::string& name, const py::object& v) {
            set_channel(*c.image, name, v);
          },
          py::arg("name"), py::arg("values"), "Same as Image.set_channel.")
      .def(
          "__delitem__",
          [](ImageChannels& c, const std::string& name) {
            channel(*c.image, name);
            c.image->channels.erase(name);
          },
          py::arg("name"), "Removes a channel; InvalidInput if missing.")
      .def(
          "__contains__",
          [](const ImageChannels& c, const std::string& name) { return c.image->channels.count(name) > 0; },
          py::arg("name"), "Whether the image has this channel.")
      .def(
          "__len__", [](const ImageChannels& c) { return c.image->channels.size(); },
          "Number of float channels.")
      .def(
          "keys",
          [](const ImageChannels& c) {
            std::vector<std::string> names;
            for (const auto& [name, values] : c.image->channels) names.push_back(name);
            return names;
          },
          "Channel names, sorted.")
      .def(
          "__iter__",
          [](const ImageChannels& c) {
            py::list names;
            for (const auto& [name, values] : c.image->channels) names.append(name);
            return py::iter(names);
          },
          "Iterates over the channel names, sorted.")
      .def(
          "items",
          [](const ImageChannels& c) {
            py::list out;
            for (const auto& [name, values] : c.image->channels)
              out.append(py::make_tuple(name, read_only(grid(values, c.image->width, c.image->height,
                                                             "channels[\"" + name + "\"]"))));
            return out;
          },
          "(name, float32 (height, width) read-only copy) pairs, sorted by name.")
      .def("__repr__", [](const ImageChannels& c) {
        std::string names;
        for (const auto& [name, values] : c.image->channels) names += (names.empty() ? "" : ", ") + name;
        return "ImageChannels(" + names + ")";
      });
}

/// Images, framebuffers and OpenEXR files.
void bind_image_type(py::module_& m) {
  py::class_<Image>(m, "Image", R"(A multi-channel, scene-referred image (framebuffer; OpenEXR contents).

Float channels by name (R G B A Z density N.x N.y N.z …), an optional uint32 `state` channel and
string attributes. Row 0 is the top of the image; arrays are (height, width).)")
      .def(py::init([](std::int64_t width, std::int64_t height) {
             Image image;
             image.width = count_arg(width, "Image: width");
             image.height = count_arg(height, "Image: height");
             return image;
           }),
           py::arg("width") = 0, py::arg("height") = 0,
           "An image of the given size with no channel. Image() (0 by 0) is the empty framebuffer that the\n"
           "render_* functions initialise. Raises InvalidInput for negative sizes.")
      .def_readonly("width", &Image::width, "Width in pixels.")
      .def_readonly("height", &Image::height, "Height in pixels.")
      .def_property_readonly(
          "channels",
          py::cpp_function([](Image& image) { return ImageChannels{&image}; }, py::keep_alive<0, 1>()),
          "The float channels, a dict-like ImageChannels view (values are float32 (height, width) copies).")
      .def(
          "set_channel", &set_channel, py::arg("name"), py::arg("values"),
          "Sets (or adds) float channel `name` from an array of shape (height, width), stored as float32.\n\n"
          "Raises InvalidInput for another shape, a non-numeric array, an empty name or the name `state`.")
      .def(
          "remove_channel",
          [](Image& image, const std::string& name) {
            channel(image, name);
            image.channels.erase(name);
          },
          py::arg("name"), "Removes float channel `name`; InvalidInput if the image has none of that name.")
      .def_property(
          "state",
          [](const Image& image) -> py::object {
            if (!image.state) return py::none();
            return grid(*image.state, image.width, image.height, "state");
          },
          [](Image& image, const py::object& values) {
            if (values.is_none()) {
              image.state.reset();
              return;
            }
            const auto v = grid_values<std::int64_t>(image, values, "Image.state", "iu");
            std::vector<std::uint32_t> state(v.size());
            for (std::size_t i = 0; i < v.size(); ++i) {
              if (v[i] < 0 || v[i] > std::int64_t{UINT32_MAX})
                throw InvalidInput("Image.state: value " + std::to_string(v[i]) +
                                   " is outside 0 … 4294967295");
              state[i] = static_cast<std::uint32_t>(v[i]);
            }
            image.state = std::move(state);
          },
          "The uint32 state channel as (height, width) (a copy), or None. Assign an integer array of shape\n"
          "(height, width) with values in 0 … 2³² − 1, or None to remove it (InvalidInput otherwise).\n"
          "Unreached pixels hold kNoState.")
      .def_property(
          "attributes",
          // Read-only view: editing a copy in place would silently do nothing.
          [](const Image& image) {
            return py::module_::import("types").attr("MappingProxyType")(py::cast(image.attributes));
          },
          [](Image& image, std::map<std::string, std::string> attributes) {
            image.attributes = std::move(attributes);
          },
          "Header attributes (str → str), a read-only mapping: assign a whole dict to change them, e.g.\n"
          "``image.attributes = {**image.attributes, \"source\": \"sweep\"}``.")
      .def(
          "copy", [](const Image& image) { return image; }, "An independent copy of the image.")
      .def("__repr__", &image_repr);

  m.def("make_framebuffer", &make_framebuffer, py::arg("camera"), py::call_guard<py::gil_scoped_release>(),
        "An empty framebuffer of the camera's size: R G B A = 0, Z = +inf, state = kNoState.\n\n"
        "Raises InvalidInput for a zero or oversized image.");
  m.def("write_exr", py::overload_cast<const std::filesystem::path&, const Image&>(&write_exr),
        py::arg("path"), py::arg("image"), py::call_guard<py::gil_scoped_release>(),
        R"(Writes every channel (32-bit FLOAT, state as UINT) and attribute of `image` to an OpenEXR file.

The file is written under a temporary name and renamed into place. Raises InvalidInput for an empty
image, an empty channel name or an attribute name reserved by OpenEXR; IoError (naming `path`)
when the file cannot be written.)");
  m.def("read_exr", &read_exr, py::arg("path"), py::arg("max_bytes") = largest_input(),
        py::call_guard<py::gil_scoped_release>(),
        "Reads an OpenEXR file into an Image (HALF and FLOAT channels as float32, UINT `state` as the\n"
        "state channel, string attributes). Raises IoError naming `path` when it is missing or unreadable,\n"
        "or when its pixels would take more than `max_bytes` (default: half the memory).");
}

void bind_image(py::module_& m) {
  bind_image_channels(m);
  bind_image_type(m);
}

/// States, segments and polylines.
void bind_raster_curves(py::module_& m) {
  m.attr("kNoState") = kNoState;

  const CurveStyle cs{};
  m.def(
      "render_segments",
      [](Image& image, const Camera& camera, const py::object& vertices, const py::object& segments,
         const py::object& states, double width, const py::object& color) {
        Segments s;
        s.vertices = points_from(vertices, "render_segments: vertices");
        s.segments = index_rows<2>(segments, "render_segments: segments");
        s.states = states_from(states, "render_segments: states");
        CurveStyle style;
        style.width = width;
        style.color = three(color, "render_segments: color");
        py::gil_scoped_release release;
        render_segments(image, camera, s, style);
      },
      py::arg("image"), py::arg("camera"), py::arg("vertices"), py::arg("segments"), py::kw_only(),
      py::arg("states") = py::none(), py::arg("width") = cs.width, py::arg("color") = tuple3(cs.color),
      R"(Draws segments as anti-aliased strokes of `width` pixels into `image` (modified in place).

vertices: float64 (V, 2|3); segments: integer (S, 2) vertex indices; states: None or S integers
(the pixels' state); color: linear RGB. The coverage across a straight stroke integrates to
`width`. An empty Image() is initialised to the camera's size. Raises InvalidInput for bad shapes
or dtypes, indices out of range, a width ≤ 0, or an image of another size than the camera.)");
  m.def(
      "render_polylines",
      [](Image& image, const Camera& camera, const py::object& polylines, double width,
         const py::object& color, bool closed) {
        const std::vector<Points> lines = nets_from(polylines, "render_polylines: polylines");
        CurveStyle style;
        style.width = width;
        style.color = three(color, "render_polylines: color");
        py::gil_scoped_release release;
        render_polylines(image, camera, lines, style, closed);
      },
      py::arg("image"), py::arg("camera"), py::arg("polylines"), py::kw_only(), py::arg("width") = cs.width,
      py::arg("color") = tuple3(cs.color), py::arg("closed").noconvert() = false,
      R"(Draws polylines (a list of float64 (n, 2|3) arrays, all with the same columns) as one segment set.

Polyline i gets state i; `closed` joins each last point to the first. Same strokes, errors and
in-place update as render_segments.)");
}

/// Meshes and points.
void bind_raster_surfaces(py::module_& m) {
  const SurfaceStyle ss{};
  m.def(
      "render_mesh",
      [](Image& image, const Camera& camera, const py::object& vertices, const py::object& triangles,
         const py::object& quads, const py::object& normals, const py::object& states,
         const py::object& color, const py::object& state_colors, double ambient, double diffuse,
         double specular, double shininess, bool headlight, const py::object& light_direction,
         int samples_per_side, std::int64_t threads) {
        // A cifs.io.Mesh as it is (any polygons, its normals, states and holes), or the arrays.
        const bool whole = py::isinstance<Mesh>(vertices);
        if (whole && !(triangles.is_none() && quads.is_none() && normals.is_none() && states.is_none()))
          throw InvalidInput(
              "render_mesh: a Mesh carries its faces, normals and states: give no triangles, quads, normals "
              "or states with it");
        SurfaceStyle style;
        style.color = three(color, "render_mesh: color");
        if (!state_colors.is_none()) {
          const Points colors = points_from(state_colors, "render_mesh: state_colors");
          if (colors.cols() != 3)
            throw InvalidInput("render_mesh: state_colors have " + std::to_string(colors.cols()) +
                               " columns, expected 3");
          for (Eigen::Index i = 0; i < colors.rows(); ++i)
            style.state_colors.push_back({colors(i, 0), colors(i, 1), colors(i, 2)});
        }
        style.ambient = ambient;
        style.diffuse = diffuse;
        style.specular = specular;
        style.shininess = shininess;
        style.headlight = headlight;
        style.light_direction = vec3(light_direction, "render_mesh: light_direction");
        style.samples_per_side = samples_per_side;
        style.threads = threads_arg(threads, "render_mesh: threads");
        Mesh mesh;
        if (whole) {
          mesh = vertices.cast<Mesh>();
        } else {
          Points V = points_from(vertices, "render_mesh: vertices");
          const auto tri = index_rows<3>(triangles, "render_mesh: triangles");
          const auto quad = index_rows<4>(quads, "render_mesh: quads");
          Points N;
          if (!normals.is_none()) N = points_from(normals, "render_mesh: normals");
          std::vector<std::uint32_t> S = states_from(states, "render_mesh: states");
          mesh = mesh_from_tables(std::move(V), tri, quad, std::move(N), std::move(S), "render_mesh");
        }
        py::gil_scoped_release release;
        render_mesh(image, camera, mesh, style);
      },
      py::arg("image"), py::arg("camera"), py::arg("vertices"), py::kw_only(),
      py::arg("triangles") = py::none(), py::arg("quads") = py::none(), py::arg("normals") = py::none(),
      py::arg("states") = py::none(), py::arg("color") = tuple3(ss.color),
      py::arg("state_colors") = py::none(), py::arg("ambient") = ss.ambient, py::arg("diffuse") = ss.diffuse,
      py::arg("specular") = ss.specular, py::arg("shininess") = ss.shininess,
      py::arg("headlight").noconvert() = ss.headlight,
      py::arg("light_direction") = tuple3(ss.light_direction),
      py::arg("samples_per_side") = ss.samples_per_side, py::arg("threads") = ss.threads,
      R"(Z-buffered, supersampled, Blinn–Phong shaded mesh rendering into `image` (in place).

vertices: float64 (V, 3), or a cifs.io.Mesh (any polygons, each drawn as its fan (0, i, i + 1), holes left
out, its normals and states; then no triangles, quads, normals or states); triangles: integer (T, 3);
quads: integer (Q, 4) (split along 0–2);
normals: None or (V, 3); states: None or one per face (triangles first); color: linear RGB;
state_colors: None or (k, 3), face f coloured state_colors[states[f] % k]; shading coefficients;
headlight or a directional light towards `light_direction`; samples_per_side² samples per pixel
(1 … 8); threads: 0 uses every core (the image does not depend on it). Writes R G B A Z N.x N.y N.z
and state. Raises InvalidInput for a bad mesh, bad shapes or dtypes, samples_per_side outside
1 … 8, or an image of another size than the camera.)");

  const PointStyle ps{};
  m.def(
      "render_points",
      [](Image& image, const Camera& camera, const py::object& points, const py::object& states,
         const py::object& color, double weight) {
        const Points P = points_from(points, "render_points: points");
        const std::vector<std::uint32_t> s = states_from(states, "render_points: states");
        PointStyle style;
        style.color = three(color, "render_points: color");
        style.weight = weight;
        py::gil_scoped_release release;
        render_points(image, camera, P, s, style);
      },
      py::arg("image"), py::arg("camera"), py::arg("points"), py::kw_only(), py::arg("states") = py::none(),
      py::arg("color") = tuple3(ps.color), py::arg("weight") = ps.weight,
      R"(Splats points (float64 (n, 2|3)) into `image` (in place): each visible point adds `weight` to the
`density` of its pixel; hit pixels get A = 1, R G B = color, Z and state (None or n integers) of
the nearest point. Raises InvalidInput for non-finite points, a column count other than 2 or 3, a
states size mismatch or an image of another size than the camera.)");
}

/// The chaos-game density.
void bind_raster_chaos(py::module_& m) {
  py::class_<ChaosDensityResult>(m, "ChaosDensityResult", "What chaos_density did: samples, outside, depth.")
      .def_readonly("samples", &ChaosDensityResult::samples, "Points drawn.")
      .def_readonly("outside", &ChaosDensityResult::outside,
                    "Points off screen or in front of the near plane (not in the density).")
      .def_readonly("depth", &ChaosDensityResult::depth, "Depth of the sampled nodes (chosen or given).")
      .def("__repr__", [](const ChaosDensityResult& r) {
        return "ChaosDensityResult(samples=" + std::to_string(r.samples) +
               ", outside=" + std::to_string(r.outside) + ", depth=" + std::to_string(r.depth) + ")";
      });

  const ChaosDensityOptions co{};
  m.attr("kDensityChunk") = kDensityChunk;
  m.def(
      "chaos_density",
      [](Image& image, const Camera& camera, const automata::Automaton& automaton, const py::object& nets,
         std::int64_t samples, std::uint64_t seed, std::int64_t threads, int depth, double pixel_tolerance,
         bool rational, const py::object& color, bool progress) {
        const std::vector<Points> N = nets_from(nets, "chaos_density: nets");
        ChaosDensityOptions o;
        o.samples = count_arg(samples, "chaos_density: samples");
        o.seed = seed;
        o.threads = threads_arg(threads, "chaos_density: threads");
        o.depth = depth;
        o.pixel_tolerance = pixel_tolerance;
        o.rational = rational;
        o.color = three(color, "chaos_density: color");
        py::gil_scoped_release release;
        ProgressBar bar("chaos density", !progress);
        o.progress = std::ref(bar);
        return chaos_density(image, camera, automaton, N, o);
      },
      py::arg("image"), py::arg("camera"), py::arg("automaton"), py::arg("nets"), py::kw_only(),
      py::arg("samples") = co.samples, py::arg("seed") = co.seed, py::arg("threads") = co.threads,
      py::arg("depth") = co.depth, py::arg("pixel_tolerance") = co.pixel_tolerance,
      py::arg("rational").noconvert() = co.rational, py::arg("color") = tuple3(co.color),
      py::arg("progress").noconvert() = false,
      R"(The chaos game of a controlled IFS added to the `density` channel of `image` (in place).

automaton: cifs.automata.Automaton; nets: one float64 array per initial entry, (size(state), 2|3),
or one more (weight) column with rational=True. Each sample is an independent random descent of
`depth` levels (0: the smallest depth within `pixel_tolerance` pixels, capped at 64) to the start
point of the node reached. Hit pixels get density += hits, A = 1, R G B = color, Z and state of the
nearest point. A seed gives the same image for any `threads` (0: every core). progress=True draws
a progress bar on stderr when it is a terminal. Returns ChaosDensityResult. Raises InvalidInput for
an invalid automaton or nets, a system that is not contractive (automatic depth), samples ≥ 2³²,
depth outside 0 … 64, rational without depth, or an image of another size than the camera.)");
}

void bind_raster(py::module_& m) {
  bind_raster_curves(m);
  bind_raster_surfaces(m);
  bind_raster_chaos(m);
}

/// PNG files and the log-density tone mapping.
void bind_png_files(py::module_& m) {
  py::enum_<PixelFormat>(m, "PixelFormat", "Interleaved 8-bit pixel layouts.")
      .value("rgb8", PixelFormat::rgb8, "3 bytes per pixel: R G B.")
      .value("rgba8", PixelFormat::rgba8, "4 bytes per pixel: R G B A.")
      .def_property_readonly("value", &enum_value<PixelFormat>, "The integer value (bytes per pixel).");

  m.def(
      "write_png",
      [](const std::filesystem::path& path, const py::object& pixels) {
        const py::array a = numeric(pixels, "write_png: pixels", "iuf");
        if (!a.dtype().is(py::dtype::of<std::uint8_t>()))
          throw InvalidInput("write_png: pixels must be a uint8 array, got dtype " +
                             std::string(py::str(a.dtype())));
        if (a.ndim() != 3 || (a.shape(2) != 3 && a.shape(2) != 4))
          throw InvalidInput("write_png: pixels must have shape (height, width, 3|4), got " + shape_text(a));
        const auto c = py::array_t<std::uint8_t, py::array::c_style>::ensure(a);
        const auto width = static_cast<std::size_t>(c.shape(1)),
                   height = static_cast<std::size_t>(c.shape(0));
        const PixelFormat format = c.shape(2) == 3 ? PixelFormat::rgb8 : PixelFormat::rgba8;
        const std::span<const std::uint8_t> bytes(c.data(), static_cast<std::size_t>(c.size()));
        py::gil_scoped_release release;
        write_png(path, bytes, width, height, format);
      },
      py::arg("path"), py::arg("pixels"),
      "Writes an 8-bit PNG from uint8 pixels of shape (height, width, 3) (RGB) or (height, width, 4) "
      "(RGBA),\n"
      "row 0 at the top (temporary file, then rename).\n\n"
      "Raises InvalidInput for another dtype or shape or an empty image; IoError naming `path` when the\n"
      "file cannot be written.");
  m.def(
      "read_png",
      [](const std::filesystem::path& path, PixelFormat format, std::uint64_t max_bytes) {
        PngImage png;
        {
          py::gil_scoped_release release;
          png = read_png(path, format, max_bytes);
        }
        return pixel_array(png.pixels, png.width, png.height, channel_count(png.format));
      },
      py::arg("path"), py::arg("format") = PixelFormat::rgba8, py::arg("max_bytes") = largest_input(),
      "Reads any PNG as uint8 (height, width, 3|4) (PixelFormat.rgb8 or rgba8). Raises IoError naming "
      "`path`,\nalso when its pixels would take more than `max_bytes` (default: half the memory).");

  const ToneMapOptions t{};
  m.def(
      "tone_map_log_density",
      [](const py::object& density, double max_density, double gamma, const py::object& ramp) {
        const py::array a = numeric(density, "tone_map_log_density: density", "iuf");
        const auto d = py::array_t<float, py::array::c_style | py::array::forcecast>::ensure(a);
        ToneMapOptions o;
        o.max_density = max_density;
        o.gamma = gamma;
        o.ramp = rgb8_rows(ramp, "tone_map_log_density: ramp");
        std::vector<std::uint8_t> rgb;
        {
          py::gil_scoped_release release;
          rgb = tone_map_log_density(std::span<const float>(d.data(), static_cast<std::size_t>(d.size())), o);
        }
        std::vector<py::ssize_t> shape(a.shape(), a.shape() + a.ndim());
        shape.push_back(3);
        py::array_t<std::uint8_t> out(shape);
        if (!rgb.empty()) std::memcpy(out.mutable_data(), rgb.data(), rgb.size());
        return out;
      },
      py::arg("density"), py::kw_only(), py::arg("max_density") = t.max_density, py::arg("gamma") = t.gamma,
      py::arg("ramp") = rgb8_list(t.ramp),
      (std::string(
           R"(Log-density tone mapping: each value d of `density` (any shape) becomes the ramp's colour at
v = (log(1 + d) / log(1 + max)) clamped to [0, 1], then v^(1/gamma).

max_density: density at the top of the ramp (0: the data's maximum); ramp: )") +
       kRampDoc + R"(.
Negative and non-finite values count as 0. Returns uint8 of shape density.shape + (3,). Raises
InvalidInput for an empty ramp, values outside 0 … 255, or gamma ≤ 0.)")
          .c_str());
}

/// Previews of an image.
void bind_png_preview(py::module_& m) {
  py::enum_<PreviewMode>(m, "PreviewMode", "What preview_rgb8 shows.")
      .value("automatic", PreviewMode::automatic,
             "density when the image has a positive density, else shaded.")
      .value("density", PreviewMode::density, "tone_map_log_density of the density channel.")
      .value("shaded", PreviewMode::shaded, "R G B composited over the background, times exposure, as sRGB.")
      .def_property_readonly("value", &enum_value<PreviewMode>, "The integer value.");

  const PreviewOptions p{};
  const char* preview_doc = R"(

mode: PreviewMode; max_density, gamma, ramp: the tone mapping of density previews (see
tone_map_log_density); background: 3 integers (8-bit sRGB) under shaded previews; exposure: factor
on the linear colour. Raises InvalidInput when a channel the mode needs is missing or of the wrong
size, or exposure is negative or not finite.)";
  m.def(
      "preview_rgb8",
      [](const Image& image, PreviewMode mode, double max_density, double gamma, const py::object& ramp,
         const py::object& background, double exposure) {
        const PreviewOptions o =
            preview_options(mode, max_density, gamma, ramp, background, exposure, "preview_rgb8");
        std::vector<std::uint8_t> rgb;
        {
          py::gil_scoped_release release;
          rgb = preview_rgb8(image, o);
        }
        return pixel_array(rgb, image.width, image.height, 3);
      },
      py::arg("image"), py::kw_only(), py::arg("mode") = p.mode, py::arg("max_density") = p.tone.max_density,
      py::arg("gamma") = p.tone.gamma, py::arg("ramp") = rgb8_list(p.tone.ramp),
      py::arg("background") = py::make_tuple(p.background[0], p.background[1], p.background[2]),
      py::arg("exposure") = p.exposure,
      (std::string("The 8-bit preview of an image as uint8 (height, width, 3), row 0 at the top.") +
       preview_doc)
          .c_str());
  m.def(
      "preview_png",
      [](const std::filesystem::path& path, const Image& image, PreviewMode mode, double max_density,
         double gamma, const py::object& ramp, const py::object& background, double exposure) {
        const PreviewOptions o =
            preview_options(mode, max_density, gamma, ramp, background, exposure, "preview_png");
        py::gil_scoped_release release;
        preview_png(path, image, o);
      },
      py::arg("path"), py::arg("image"), py::kw_only(), py::arg("mode") = p.mode,
      py::arg("max_density") = p.tone.max_density, py::arg("gamma") = p.tone.gamma,
      py::arg("ramp") = rgb8_list(p.tone.ramp),
      py::arg("background") = py::make_tuple(p.background[0], p.background[1], p.background[2]),
      py::arg("exposure") = p.exposure,
      (std::string("Writes preview_rgb8 of `image` as a PNG (IoError naming `path` when it cannot).") +
       preview_doc)
          .c_str());
}

void bind_png(py::module_& m) {
  bind_png_files(m);
  bind_png_preview(m);
}

void bind_point_ifs(py::module_& m) {
  py::class_<Bounds>(m, "Bounds",
                     "A closed window [x_min, x_max] × [y_min, y_max] of the plane; row 0 of a "
                     "histogram is at y_max.")
      .def(py::init([](double x_min, double x_max, double y_min, double y_max) {
             return Bounds{x_min, x_max, y_min, y_max};
           }),
           py::kw_only(), py::arg("x_min") = Bounds{}.x_min, py::arg("x_max") = Bounds{}.x_max,
           py::arg("y_min") = Bounds{}.y_min, py::arg("y_max") = Bounds{}.y_max,
           "A window from keyword arguments (checked where it is used).")
      .def_readwrite("x_min", &Bounds::x_min, "Left edge.")
      .def_readwrite("x_max", &Bounds::x_max, "Right edge.")
      .def_readwrite("y_min", &Bounds::y_min, "Bottom edge.")
      .def_readwrite("y_max", &Bounds::y_max, "Top edge (row 0).")
      .def("__repr__", &bounds_repr);

  m.def(
      "estimate_bounds",
      [](const std::vector<AffineMap>& maps, double margin, std::int64_t points) {
        const std::uint64_t n = count_arg(points, "estimate_bounds: points");
        py::gil_scoped_release release;
        return estimate_bounds(maps, margin, n);
      },
      py::arg("maps"), py::arg("margin") = 0.02, py::arg("points") = 100000,
      "Bounding box of `points` chaos-game points of the affine IFS `maps` (a list of cifs.ifs.AffineMap),\n"
      "widened by `margin` times its size on every side: a framing helper, not a proof.\n\n"
      "Raises InvalidInput for invalid maps or a negative margin or point count.");

  py::class_<Histogram>(m, "Histogram", "The chaos-game histogram of a point IFS.")
      .def_readonly("width", &Histogram::width, "Columns.")
      .def_readonly("height", &Histogram::height, "Rows.")
      .def_property_readonly(
          "bounds", [](const Histogram& h) { return h.bounds; },
          "The window binned (row 0 at y_max), a copy.")
      .def_property_readonly(
          "counts", [](const Histogram& h) { return grid(h.counts, h.width, h.height, "counts"); },
          "Hits per pixel, uint32 (height, width) (a copy).")
      .def_readonly("samples", &Histogram::samples, "Points generated.")
      .def_readonly("outside", &Histogram::outside, "Points outside the bounds (not in counts).")
      .def("__repr__", [](const Histogram& h) {
        return "Histogram(" + std::to_string(h.width) + " by " + std::to_string(h.height) +
               ", samples=" + std::to_string(h.samples) + ", outside=" + std::to_string(h.outside) + ")";
      });

  const ChaosHistogramOptions h{};
  m.attr("kChaosChunk") = kChaosChunk;
  m.def(
      "chaos_game_histogram",
      [](const std::vector<AffineMap>& maps, std::int64_t samples, std::uint64_t seed, std::int64_t threads,
         std::int64_t width, std::int64_t height, const Bounds& bounds, std::int64_t burn_in, bool progress) {
        ChaosHistogramOptions o;
        o.samples = count_arg(samples, "chaos_game_histogram: samples");
        o.seed = seed;
        o.threads = threads_arg(threads, "chaos_game_histogram: threads");
        o.width = count_arg(width, "chaos_game_histogram: width");
        o.height = count_arg(height, "chaos_game_histogram: height");
        o.bounds = bounds;
        o.burn_in = count_arg(burn_in, "chaos_game_histogram: burn_in");
        py::gil_scoped_release release;
        ProgressBar bar("chaos game", !progress);
        o.progress = std::ref(bar);
        return chaos_game_histogram(maps, o);
      },
      py::arg("maps"), py::kw_only(), py::arg("samples") = h.samples, py::arg("seed") = h.seed,
      py::arg("threads") = h.threads, py::arg("width") = h.width, py::arg("height") = h.height,
      py::arg("bounds") = h.bounds, py::arg("burn_in") = h.burn_in, py::arg("progress").noconvert() = false,
      R"(The chaos game of an affine IFS (a list of cifs.ifs.AffineMap, maps drawn with their probabilities)
binned into a width × height Histogram over `bounds`.

A seed gives the same counts for any `threads` (0: every core). burn_in: points dropped at the start
of every chunk. progress=True draws a progress bar on stderr when it is a terminal. Raises
InvalidInput for no maps, non-finite coefficients, bad probabilities, a map that is not a
contraction, an empty image, empty bounds, samples ≥ 2³², or negative counts.)");
  m.def(
      "hutchinson_measure",
      [](const std::vector<AffineMap>& maps, std::int64_t depth, std::int64_t width, std::int64_t height,
         const Bounds& bounds) {
        const auto k = threads_arg(depth, "hutchinson_measure: depth");
        const auto w = count_arg(width, "hutchinson_measure: width"),
                   hh = count_arg(height, "hutchinson_measure: height");
        std::vector<double> mass;
        {
          py::gil_scoped_release release;
          mass = hutchinson_measure(maps, k, w, hh, bounds);
        }
        return grid(mass, w, hh, "hutchinson_measure");
      },
      py::arg("maps"), py::arg("depth"), py::arg("width"), py::arg("height"), py::arg("bounds"),
      R"(The invariant measure of an affine IFS at depth k, binned: float64 (height, width) masses (row 0 at
bounds.y_max) summing to the mass inside the bounds. Every word of k maps carries the product of
its probabilities, placed at the word's image of the measure's barycentre. Raises InvalidInput for
invalid maps, an empty image, empty bounds, a negative depth or more than 2²⁸ points.)");
  m.def(
      "hutchinson_points",
      [](const std::vector<AffineMap>& maps, std::int64_t depth, std::int64_t max_points) {
        const auto k = threads_arg(depth, "hutchinson_points: depth");
        const auto limit = count_arg(max_points, "hutchinson_points: max_points");
        HutchinsonPoints words;
        {
          py::gil_scoped_release release;
          words = hutchinson_points(maps, k, limit);
        }
        const auto n = static_cast<py::ssize_t>(words.mass.size());
        return py::make_tuple(py::cast(std::move(words.points)), py::array_t<double>(n, words.mass.data()),
                              py::array_t<std::uint32_t>(n, words.map.data()));
      },
      py::arg("maps"), py::arg("depth"), py::kw_only(), py::arg("max_points") = std::int64_t{1} << 22,
      R"(The points that hutchinson_measure bins, in its walk's order: (points, mass, map) — float64 (n, 2) images
of the measure's barycentre under every word of `depth` maps of non-zero probability, float64 (n,) the
words' masses, uint32 (n,) the map applied last (the top-level piece holding the point). What cifs view
draws of a classic IFS. Raises InvalidInput as hutchinson_measure, and before any work when
(#maps)^depth exceeds max_points.)");
}

}  // namespace

void bind_render(py::module_& m) {
  bind_camera(m);
  bind_image(m);
  bind_raster(m);
  bind_png(m);
  bind_point_ifs(m);
}

}  // namespace cifs::python
