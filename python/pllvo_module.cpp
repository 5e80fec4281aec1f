// The Python module `pllvo._pllvo` (re-exported by the package `pllvo`): the library API
// (pllvo/api/odometry.h) with numpy arrays in and out, plus run() and evaluate(), which return
// what `pllvo run` and `pllvo eval --json` write. Errors are Python exceptions carrying pllvo's
// message (pllvo.InputError for bad input, a ValueError); the GIL is released while tracking.
#include <pybind11/functional.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>
#include <pybind11/stl/filesystem.h>

#include <cstring>
#include <memory>

#include "pllvo/api/dataset.h"
#include "pllvo/api/odometry.h"
#include "pllvo/eval/eval_report.h"
#include "pllvo/io/sequence.h"
#include "pllvo/report/config_overrides.h"
#include "pllvo/vo/run_sequence.h"

namespace py = pybind11;

namespace {

/// A view of a uint8 array as a cv::Mat (no copy): (H, W) gray, (H, W, 3) BGR or (H, W, 4) BGRA.
/// TypeError for another dtype, ValueError for another shape.
cv::Mat image_view(const py::object& object, const char* which) {
  if (object.is_none()) return cv::Mat();
  if (!py::isinstance<py::array>(object))
    throw py::type_error(std::string(which) + " image: expected a numpy array, got " +
                         py::str(py::type::of(object)).cast<std::string>());
  auto array = py::reinterpret_borrow<py::array>(object);
  if (!array.dtype().is(py::dtype::of<uint8_t>()))
    throw py::type_error(std::string(which) + " image: expected dtype uint8, got " +
                         py::str(array.dtype()).cast<std::string>());
  const bool colour = array.ndim() == 3 && (array.shape(2) == 3 || array.shape(2) == 4);
  if (array.ndim() != 2 && !colour)
    throw py::value_error(std::string(which) + " image: expected shape (H, W), (H, W, 3) or (H, W, 4), got ndim " +
                          std::to_string(array.ndim()));
  if (!(array.flags() & py::array::c_style))
    throw py::value_error(std::string(which) + " image: the array must be C-contiguous (numpy.ascontiguousarray)");
  const int channels = array.ndim() == 3 ? static_cast<int>(array.shape(2)) : 1;
  return cv::Mat(static_cast<int>(array.shape(0)), static_cast<int>(array.shape(1)), CV_8UC(channels),
                 const_cast<void*>(array.data()));
}

/// A view of a depth array as a cv::Mat (no copy): (H, W) uint16 in the calibration's units per
/// metre or float32 metres. TypeError for another dtype, ValueError for another shape.
cv::Mat depth_view(const py::object& object) {
  if (object.is_none()) return cv::Mat();
  if (!py::isinstance<py::array>(object))
    throw py::type_error("depth image: expected a numpy array, got " + py::str(py::type::of(object)).cast<std::string>());
  auto array = py::reinterpret_borrow<py::array>(object);
  const bool u16 = array.dtype().is(py::dtype::of<uint16_t>()), f32 = array.dtype().is(py::dtype::of<float>());
  if (!u16 && !f32)
    throw py::type_error("depth image: expected dtype uint16 or float32, got " + py::str(array.dtype()).cast<std::string>());
  if (array.ndim() != 2) throw py::value_error("depth image: expected shape (H, W), got ndim " + std::to_string(array.ndim()));
  if (!(array.flags() & py::array::c_style))
    throw py::value_error("depth image: the array must be C-contiguous (numpy.ascontiguousarray)");
  return cv::Mat(static_cast<int>(array.shape(0)), static_cast<int>(array.shape(1)), u16 ? CV_16UC1 : CV_32FC1,
                 const_cast<void*>(array.data()));
}

/// A CV_32FC1 depth image as a float32 numpy array (a copy); None when empty.
py::object depth_to_numpy(const cv::Mat& depth) {
  if (depth.empty()) return py::none();
  const cv::Mat m = depth.isContinuous() ? depth : depth.clone();
  py::array_t<float> a({static_cast<py::ssize_t>(m.rows), static_cast<py::ssize_t>(m.cols)});
  std::memcpy(a.mutable_data(), m.data, m.total() * m.elemSize());
  return std::move(a);
}

py::array_t<double> to_numpy(const Eigen::Matrix4d& m) {
  py::array_t<double> a({4, 4});
  auto r = a.mutable_unchecked<2>();
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j) r(i, j) = m(i, j);
  return a;
}

/// One row per vector: (N, D).
template <typename Scalar, int D>
py::array_t<Scalar> rows(const std::vector<Eigen::Matrix<Scalar, D, 1>>& vectors) {
  py::array_t<Scalar> a({static_cast<py::ssize_t>(vectors.size()), py::ssize_t{D}});
  auto m = a.template mutable_unchecked<2>();
  for (size_t i = 0; i < vectors.size(); ++i)
    for (int j = 0; j < D; ++j) m(i, j) = vectors[i](j);
  return a;
}

/// (stamps (N,), poses (N, 4, 4)).
py::tuple to_numpy(const std::vector<pllvo::StampedPose>& poses) {
  const auto n = static_cast<py::ssize_t>(poses.size());
  py::array_t<double> stamps(n);
  py::array_t<double> matrices({n, py::ssize_t{4}, py::ssize_t{4}});
  auto s = stamps.mutable_unchecked<1>();
  auto m = matrices.mutable_unchecked<3>();
  for (py::ssize_t k = 0; k < n; ++k) {
    s(k) = poses[k].timestamp;
    for (int i = 0; i < 4; ++i)
      for (int j = 0; j < 4; ++j) m(k, i, j) = poses[k].T_world_cam0(i, j);
  }
  return py::make_tuple(stamps, matrices);
}

/// A cv::Mat as a numpy uint8 array (a copy): (H, W) or (H, W, C); None when empty.
py::object to_numpy(const cv::Mat& image) {
  if (image.empty()) return py::none();
  const cv::Mat m = image.isContinuous() ? image : image.clone();
  std::vector<py::ssize_t> shape{m.rows, m.cols};
  if (m.channels() > 1) shape.push_back(m.channels());
  py::array_t<uint8_t> a(shape);
  std::memcpy(a.mutable_data(), m.data, m.total() * m.elemSize());
  return std::move(a);
}

py::object json_to_python(const std::string& text) { return py::module_::import("json").attr("loads")(text); }

/// Python values of an overrides dict as YAML scalars ("false", "3", "orb").
std::vector<std::pair<std::string, std::string>> overrides_from(const py::dict& overrides) {
  std::vector<std::pair<std::string, std::string>> out;
  for (const auto& [key, value] : overrides) {
    std::string text;
    if (py::isinstance<py::bool_>(value))
      text = value.cast<bool>() ? "true" : "false";
    else
      text = py::str(value).cast<std::string>();
    out.emplace_back(py::str(key).cast<std::string>(), text);
  }
  return out;
}

/// Destroys the odometry without the GIL: its tracking thread may be waiting for it in a callback.
struct PyOdometry {
  std::unique_ptr<pllvo::Odometry> odometry;
  ~PyOdometry() {
    py::gil_scoped_release release;
    odometry.reset();
  }
};

pllvo::OdometryOptions odometry_options(const std::string& config, const py::dict& overrides, bool stereo,
                                        bool single_thread, bool live, const std::string& models_dir) {
  pllvo::OdometryOptions o;
  o.config_yaml = config;
  o.overrides = overrides_from(overrides);
  o.stereo = stereo;
  o.single_thread = single_thread;
  o.live = live;
  if (!models_dir.empty()) o.models_dir = models_dir;
  return o;
}

py::object run(const std::string& dataset, const std::string& out, const std::string& config, const py::dict& overrides,
               bool mono, bool single_thread, size_t first, size_t max_frames, bool realtime, double speed,
               const std::string& format, const std::string& camera, const std::string& models_dir) {
  auto options = odometry_options(config, overrides, !mono, single_thread, realtime, models_dir);
  std::string stats;
  {
    py::gil_scoped_release release;
    pllvo::io::SequenceOptions sequence_options;
    sequence_options.format = format;
    sequence_options.camera_yaml = camera;
    sequence_options.mono = mono;
    const auto sequence = pllvo::io::open_sequence(dataset, sequence_options);
    const pllvo::vo::VoConfig vo_config = pllvo::vo_config_of(options);
    pllvo::vo::RunOptions run_options;
    run_options.out_dir = out;
    run_options.stereo = !mono;
    run_options.first_frame = first;
    run_options.max_frames = max_frames;
    run_options.realtime = realtime;
    run_options.speed = speed;
    stats = pllvo::vo::run_sequence(*sequence, vo_config, run_options).stats.dump();
  }
  return json_to_python(stats);
}

py::object evaluate(const std::string& est, const std::string& ref, const std::string& metric,
                    const std::vector<std::string>& relations, const std::string& align, const std::string& ref_format,
                    long n_to_align, bool align_origin, std::optional<double> t_max_diff,
                    std::optional<double> t_offset, std::optional<double> delta, const std::string& delta_unit,
                    std::optional<double> delta_tol, bool all_pairs, bool pairs_from_reference) {
  namespace eval = pllvo::eval;
  eval::EvalRequest request;
  request.est_file = est;
  request.ref_file = ref;
  request.ref_format = eval::parse_trajectory_format(ref_format);
  request.metrics = eval::parse_metrics(metric);
  request.relations.clear();
  for (const auto& r : relations) request.relations.push_back(eval::parse_pose_relation(r));
  eval::EvalOptions& o = request.options;
  o.align = eval::parse_align_mode(align);
  o.n_to_align = n_to_align;
  o.align_origin = align_origin;
  if (t_max_diff) o.association.t_max_diff = *t_max_diff;
  if (t_offset) o.association.t_offset = *t_offset;
  if (delta) o.rpe.delta = *delta;
  o.rpe.unit = eval::parse_delta_unit(delta_unit);
  if (delta_tol) o.rpe.delta_tol = *delta_tol;
  o.rpe.all_pairs = all_pairs;
  o.pairs_from_reference = pairs_from_reference;
  std::string json;
  {
    py::gil_scoped_release release;
    json = eval::report_to_json(eval::run_evaluation(request)).dump();
  }
  return json_to_python(json);
}

}  // namespace

PYBIND11_MODULE(_pllvo, m) {
  m.doc() = "pllvo: point-line visual odometry (SuperPoint, LightGlue, EDLines, sliding-window BA)";
  auto input_error = py::register_exception<pllvo::InputError>(m, "InputError", PyExc_ValueError);
  (void)input_error;

  py::class_<pllvo::CameraIntrinsics>(m, "CameraIntrinsics")
      .def(py::init([](int width, int height, double fx, double fy, double cx, double cy,
                       const std::string& distortion_model, const std::vector<double>& distortion) {
             return pllvo::CameraIntrinsics{width, height, fx, fy, cx, cy, distortion_model, distortion};
           }),
           py::arg("width"), py::arg("height"), py::arg("fx"), py::arg("fy"), py::arg("cx"), py::arg("cy"),
           py::arg("distortion_model") = "none", py::arg("distortion") = std::vector<double>{})
      .def_readwrite("width", &pllvo::CameraIntrinsics::width)
      .def_readwrite("height", &pllvo::CameraIntrinsics::height)
      .def_readwrite("fx", &pllvo::CameraIntrinsics::fx)
      .def_readwrite("fy", &pllvo::CameraIntrinsics::fy)
      .def_readwrite("cx", &pllvo::CameraIntrinsics::cx)
      .def_readwrite("cy", &pllvo::CameraIntrinsics::cy)
      .def_readwrite("distortion_model", &pllvo::CameraIntrinsics::distortion_model)
      .def_readwrite("distortion", &pllvo::CameraIntrinsics::distortion);

  py::class_<pllvo::Calibration>(m, "Calibration")
      .def_static("load", [](const std::string& path) { return pllvo::Calibration::load(path); }, py::arg("path"),
                  "a dataset folder, pllvo's camera YAML or a EuRoC sensor.yaml")
      .def_static("mono", &pllvo::Calibration::mono, py::arg("camera"))
      .def_static("stereo_pair",
                  [](const pllvo::CameraIntrinsics& left, const pllvo::CameraIntrinsics& right,
                     const Eigen::Matrix4d& T_left_right) {
                    Eigen::Isometry3d T;
                    T.matrix() = T_left_right;
                    return pllvo::Calibration::stereo_pair(left, right, T);
                  },
                  py::arg("left"), py::arg("right"), py::arg("T_left_right"))
      .def_property_readonly("stereo", &pllvo::Calibration::stereo)
      .def_property_readonly("width", &pllvo::Calibration::width)
      .def_property_readonly("height", &pllvo::Calibration::height)
      .def_property_readonly("baseline", &pllvo::Calibration::baseline)
      .def("left_only", &pllvo::Calibration::left_only)
      .def("with_depth", &pllvo::Calibration::with_depth, py::arg("units_per_metre"),
           "RGB-D: depth images registered to the camera; uint16 ones hold units_per_metre per metre")
      .def_property_readonly("depth", &pllvo::Calibration::depth)
      .def_property_readonly("depth_units_per_metre", &pllvo::Calibration::depth_units_per_metre);

  py::class_<pllvo::Dataset>(m, "Dataset")
      .def(py::init([](const std::string& folder, bool mono) { return std::make_unique<pllvo::Dataset>(folder, mono); }),
           py::arg("folder"), py::arg("mono") = false)
      .def("__len__", &pllvo::Dataset::size)
      .def("frame",
           [](const pllvo::Dataset& d, size_t i, bool with_depth) {
             if (i >= d.size()) throw py::index_error("frame " + std::to_string(i) + " of " + std::to_string(d.size()));
             pllvo::DatasetFrame f;
             {
               py::gil_scoped_release release;
               f = d.frame(i);
             }
             if (with_depth) return py::make_tuple(f.timestamp, to_numpy(f.left), to_numpy(f.right), depth_to_numpy(f.depth));
             return py::make_tuple(f.timestamp, to_numpy(f.left), to_numpy(f.right));
           },
           py::arg("i"), py::arg("with_depth") = false,
           "(timestamp, left, right or None); with_depth: and the depth image (float32 metres) or None")
      .def_property_readonly("calibration", &pllvo::Dataset::calibration)
      .def("ground_truth", [](const pllvo::Dataset& d) { return to_numpy(d.ground_truth()); },
           "(stamps (N,), T_world_cam0 (N, 4, 4)); empty arrays when the dataset has none");

  py::class_<pllvo::TrackResult>(m, "TrackResult")
      .def_readonly("frame_index", &pllvo::TrackResult::frame_index)
      .def_readonly("timestamp", &pllvo::TrackResult::timestamp)
      .def_property_readonly("state", [](const pllvo::TrackResult& r) { return pllvo::to_string(r.state); })
      .def_readonly("tracked", &pllvo::TrackResult::tracked)
      .def_property_readonly("T_world_cam0", [](const pllvo::TrackResult& r) { return to_numpy(r.T_world_cam0); })
      .def_readonly("tracked_points", &pllvo::TrackResult::tracked_points)
      .def_readonly("tracked_lines", &pllvo::TrackResult::tracked_lines)
      .def_readonly("keyframe", &pllvo::TrackResult::keyframe)
      .def_readonly("map_segment", &pllvo::TrackResult::map_segment)
      .def_property_readonly("points", [](const pllvo::TrackResult& r) { return rows(r.points); })
      .def_readonly("point_in_map", &pllvo::TrackResult::point_in_map)
      .def_property_readonly("lines", [](const pllvo::TrackResult& r) { return rows(r.lines); });

  py::class_<PyOdometry>(m, "Odometry")
      .def(py::init([](const pllvo::Calibration& calibration, const std::string& config, const py::dict& overrides,
                       bool stereo, bool single_thread, bool live, const std::string& models_dir) {
             auto options = odometry_options(config, overrides, stereo, single_thread, live, models_dir);
             auto p = std::make_unique<PyOdometry>();
             py::gil_scoped_release release;
             p->odometry = std::make_unique<pllvo::Odometry>(calibration, options);
             return p;
           }),
           py::arg("calibration"), py::arg("config") = "", py::arg("overrides") = py::dict(), py::arg("stereo") = true,
           py::arg("single_thread") = false, py::arg("live") = false, py::arg("models_dir") = "")
      .def("track",
           [](PyOdometry& self, double timestamp, const py::object& left, const py::object& right) {
             const cv::Mat l = image_view(left, "left");
             const cv::Mat r = image_view(right, "right");
             py::gil_scoped_release release;
             return self.odometry->track(timestamp, l, r);
           },
           py::arg("timestamp"), py::arg("left"), py::arg("right") = py::none())
      .def("push",
           [](PyOdometry& self, double timestamp, const py::object& left, const py::object& right) {
             const cv::Mat l = image_view(left, "left");
             const cv::Mat r = image_view(right, "right");
             py::gil_scoped_release release;
             return self.odometry->push(timestamp, l, r);
           },
           py::arg("timestamp"), py::arg("left"), py::arg("right") = py::none(),
           "hand a frame to the tracking thread; True when it replaced a frame still waiting (dropped)")
      .def("track_rgbd",
           [](PyOdometry& self, double timestamp, const py::object& image, const py::object& depth) {
             const cv::Mat l = image_view(image, "image");
             const cv::Mat d = depth_view(depth);
             py::gil_scoped_release release;
             return self.odometry->track_rgbd(timestamp, l, d);
           },
           py::arg("timestamp"), py::arg("image"), py::arg("depth"),
           "RGB-D: an image and its depth (uint16 in the calibration's units per metre, or float32 metres)")
      .def("push_rgbd",
           [](PyOdometry& self, double timestamp, const py::object& image, const py::object& depth) {
             const cv::Mat l = image_view(image, "image");
             const cv::Mat d = depth_view(depth);
             py::gil_scoped_release release;
             return self.odometry->push_rgbd(timestamp, l, d);
           },
           py::arg("timestamp"), py::arg("image"), py::arg("depth"))
      .def("on_result",
           [](PyOdometry& self, std::function<void(const pllvo::TrackResult&)> callback) {
             // pybind11's function wrapper takes the GIL for each call.
             self.odometry->on_result(std::move(callback));
           })
      .def("latest", [](const PyOdometry& self) { return self.odometry->latest(); })
      .def("finish",
           [](PyOdometry& self) {
             py::gil_scoped_release release;
             self.odometry->finish();
           })
      .def("trajectory", [](const PyOdometry& self) { return to_numpy(self.odometry->trajectory()); },
           "(stamps (N,), T_world_cam0 (N, 4, 4)) of the tracked frames")
      .def("anchored_trajectory",
           [](const PyOdometry& self) { return to_numpy(self.odometry->anchored_trajectory()); },
           "the same frames on their keyframes' bundle-adjusted poses (trajectory_anchored.tum)")
      .def("keyframes", [](const PyOdometry& self) { return to_numpy(self.odometry->keyframes()); })
      .def("map_points", [](const PyOdometry& self) { return rows(self.odometry->map_points()); })
      .def_property_readonly("stereo", [](const PyOdometry& self) { return self.odometry->stereo(); })
      .def_property_readonly("rgbd", [](const PyOdometry& self) { return self.odometry->rgbd(); })
      .def("stats", [](const PyOdometry& self) { return json_to_python(self.odometry->report().stats_json); },
           "stats.json as a dict (after finish())")
      .def("save", [](const PyOdometry& self, const std::string& dir) { self.odometry->save(dir); }, py::arg("dir"));

  m.def("run", &run, py::arg("dataset"), py::arg("out") = "", py::arg("config") = "",
        py::arg("overrides") = py::dict(), py::arg("mono") = false, py::arg("single_thread") = false,
        py::arg("first") = 0, py::arg("max_frames") = 0, py::arg("realtime") = false, py::arg("speed") = 1.0,
        py::arg("format") = "auto", py::arg("camera") = "", py::arg("models_dir") = "",
        "pllvo run DATASET: returns stats.json as a dict; writes the run's files to `out` when given");
  m.def("evaluate", &evaluate, py::arg("est"), py::arg("ref"), py::arg("metric") = "both",
        py::arg("relations") = std::vector<std::string>{"trans_part", "angle_deg"}, py::arg("align") = "none",
        py::arg("ref_format") = "auto", py::arg("n_to_align") = -1, py::arg("align_origin") = false,
        py::arg("t_max_diff") = py::none(), py::arg("t_offset") = py::none(), py::arg("delta") = py::none(),
        py::arg("delta_unit") = "frames", py::arg("delta_tol") = py::none(), py::arg("all_pairs") = false,
        py::arg("pairs_from_reference") = false,
        "pllvo eval EST REF: returns what `pllvo eval --json` writes, as a dict");
}
