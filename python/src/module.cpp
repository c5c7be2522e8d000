// The Python module `mrr` (docs/python.md): scenes, frames rendered the way `mrr render` renders
// them (the frame-parameter table's rows as keyword arguments, the same options, renderer and
// report), every stage as a numpy array by its stage-list name, the masks from Python (SPEC §3),
// the metrics (SPEC §10), and the method, parameter and stage tables.
#include "python/src/module.h"

#include <pybind11/stl.h>
#include <tbb/global_control.h>
#include <tbb/task_arena.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <atomic>
#include <map>
#include <mutex>
#include <optional>
#include <sstream>
#include <thread>
#include <tuple>

#include "common/error.h"
#include "common/frame_params.h"
#include "common/image_io.h"
#include "common/memory.h"
#include "common/methods.h"
#include "common/stage_images.h"
#include "common/stages.h"
#include "compare/metrics/flip.h"
#include "compare/metrics/metrics.h"
#include "compare/report/report.h"
#include "frontend/frame_file.h"
#include "frontend/frame_options.h"
#include "frontend/renderers.h"

namespace mrr::python {

namespace {

// The port could not start (no EGL device, no GL 3.3): RuntimeError mrr.PortUnavailable.
struct PortUnavailable : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// nlohmann JSON as Python objects (dicts, lists, numbers), through the json module.
py::object toPython(const nlohmann::json& j) { return py::module_::import("json").attr("loads")(j.dump()); }

// As `mrr render`: 0 threads is every core TBB may use (app/command_support.cpp: threadCount).
int threadCount(int requested) { return requested > 0 ? requested : tbb::this_task_arena::max_concurrency(); }

// A renderer and who uses it: one frame at a time (a renderer's scratch and the port's GL context
// are its own), and the port only on the thread that made its GL context, where it is current.
struct RendererSlot {
  std::shared_ptr<FrameRenderer> renderer;
  std::mutex busy;                      // held while a frame renders (the GIL released)
  std::atomic<std::thread::id> user{};  // the thread rendering now, if any
  std::thread::id maker = std::this_thread::get_id();
};

// A scene loaded at one request (camera, light, aspect), with the renderers made on it, by path.
struct LoadedScene {
  ResolvedScene rs;
  std::map<std::string, std::shared_ptr<RendererSlot>> renderers;

  // The path's renderer (frontend/renderers.h, the one place a path is chosen), made once.
  std::shared_ptr<RendererSlot> renderer(const std::string& path, const PathOptions& options) {
    const std::string key = path + "/" + std::to_string(options.glDevice) + "/" + options.gpuTiming;
    auto it = renderers.find(key);
    if (it != renderers.end()) return it->second;
    auto slot = std::make_shared<RendererSlot>();
    try {
      slot->renderer = makeRenderer(path, rs.scene, options);
    } catch (const std::exception& e) {
      if (path != "gpu") throw;
      throw PortUnavailable(std::string("path gpu: the GL port cannot start here: ") + e.what());
    }
    return renderers[key] = slot;
  }
};

// "--eye" and the rest of a scene request as one key: frames asking the same share a load.
std::string requestKey(const SceneRequest& r) {
  std::ostringstream k;
  const auto vec = [&](const std::optional<glm::vec3>& v) {
    if (v) k << exactFloat(v->x) << "," << exactFloat(v->y) << "," << exactFloat(v->z);
    k << ";";
  };
  k << r.scene << ";" << (r.flipUp ? int(*r.flipUp) : -1) << ";" << r.cameraIndex.value_or(-1) << ";";
  vec(r.eye);
  vec(r.target);
  vec(r.up);
  vec(r.lightToward);
  k << (r.fovDegrees ? exactFloat(*r.fovDegrees) : "") << ";" << r.skipBlendMaterials << ";" << exactFloat(r.aspect);
  return k.str();
}

// mrr.Scene: what load_scene returns, a scene by name ("builtin:demo", a shared scene's short
// name or a glTF path), loaded once per request a frame makes of it (scenes/catalog.h).
struct PyScene {
  std::string name;
  std::map<std::string, std::shared_ptr<LoadedScene>> loads;

  explicit PyScene(std::string n) : name(std::move(n)) {
    SceneRequest r;
    r.scene = name;
    resolve(r);  // loads it now: a bad name or file fails here
  }
  // The scene as `request` resolves it (the scene's default view at the frame's aspect, or the
  // camera the frame names), loaded and framed exactly as `mrr render` does (resolveScene).
  std::shared_ptr<LoadedScene> resolve(const SceneRequest& request) {
    const std::string key = requestKey(request);
    auto it = loads.find(key);
    if (it != loads.end()) return it->second;
    auto loaded = std::make_shared<LoadedScene>();
    {
      py::gil_scoped_release nogil;
      loaded->rs = resolveScene(request);
    }
    return loads[key] = loaded;
  }
  const Scene& scene() const { return loads.begin()->second->rs.scene; }
};

// A keyword argument's value as the command line's text for its row's kind (common/frame_params.h):
// size=(160, 96) is "160x96", eye=(x, y, z) "x,y,z", sigma2=[...] "v0,v1,v2,v3", a switch's
// True/False "on"/"off". Flags and level lists become words of their own (see frameWords).
std::string valueText(const FrameParamInfo& p, const py::handle& v) {
  const std::string name(p.key);
  const bool sequence = py::isinstance<py::sequence>(v) && !py::isinstance<py::str>(v);
  if (py::isinstance<py::bool_>(v)) {
    if (p.kind == ParamKind::Switch) return v.cast<bool>() ? "on" : "off";
    throw BadValue(name + "=" + std::string(py::repr(v)) + ": expected a " +
                   (p.kind == ParamKind::Int      ? "whole number"
                    : p.kind == ParamKind::Number ? "number"
                                                  : "value"));
  }
  if (sequence) {
    const py::sequence s = py::reinterpret_borrow<py::sequence>(v);
    std::string text;
    const char* sep = p.param == Param::Size ? "x" : ",";
    for (size_t i = 0; i < s.size(); ++i) text += (i ? sep : "") + std::string(py::str(s[i]));
    if (p.kind == ParamKind::Triple || p.kind == ParamKind::PerLevel || p.param == Param::Size ||
        p.param == Param::Gaze)
      return text;
    throw BadValue(name + "=" + std::string(py::repr(v)) + ": expected one value, not a sequence");
  }
  return py::str(v);
}

// The command-line words of a frame's keyword arguments, each resolved through the parameter
// table's rows (findParam: the key, "effect_cap" for --effect-cap): the same words `mrr render`
// takes, so the same frame.
std::vector<std::string> frameWords(const py::kwargs& params) {
  std::vector<std::string> words;
  for (const auto& [k, v] : params) {
    const std::string key = py::str(k);
    const FrameParamInfo* p = key.find('-') == std::string::npos ? findParam(key) : nullptr;
    if (!p || key.rfind("--", 0) == 0)
      throw BadValue("unknown frame parameter " + key +
                     " (mrr.params() lists them: the command line's options, "
                     "'-' as '_', e.g. effect_cap for --effect-cap)");
    if (p->param == Param::Scene) throw BadValue("scene: give the scene as Frame's first argument (mrr.load_scene)");
    const std::string option = optionName(p->param);
    if (v.is_none()) continue;
    if (p->kind == ParamKind::Flag) {
      if (!py::isinstance<py::bool_>(v))
        throw BadValue(key + "=" + std::string(py::repr(v)) + ": expected True or False");
      if (v.cast<bool>()) words.push_back(option);
      continue;
    }
    if (p->kind == ParamKind::Levels) {
      const py::sequence levels =
          py::isinstance<py::sequence>(v) ? py::reinterpret_borrow<py::sequence>(v) : py::sequence(py::make_tuple(v));
      for (const py::handle level : levels) words.push_back(option + "=" + std::string(py::str(level)));
      continue;
    }
    words.push_back(option + "=" + valueText(*p, v));
  }
  return words;
}

// The part and level a stage name names: "final", "mask.L1", "gbuffer.L0". KeyError when none.
std::pair<const PartInfo*, int> parseStage(const std::string& name) {
  std::string base = name;
  int level = -1;
  const size_t dot = name.rfind(".L");
  if (dot != std::string::npos && dot + 2 < name.size() &&
      std::all_of(name.begin() + static_cast<long>(dot) + 2, name.end(), ::isdigit) && name.size() - dot <= 4) {
    base = name.substr(0, dot);
    level = std::stoi(name.substr(dot + 2));
  }
  for (const PartInfo& p : kParts) {
    if (p.name != base) continue;
    if (p.perLevel && level < 0)
      throw py::key_error(name + ": a stage per level; name one, " + partName(p.part, 0) + " .. " +
                          partName(p.part, kLevelCount - 1));
    if (!p.perLevel && level >= 0) throw py::key_error(name + ": " + base + " is not per level; name it " + base);
    if (level >= kLevelCount)
      throw py::key_error(name + ": level " + std::to_string(level) + " is not in 0.." +
                          std::to_string(kLevelCount - 1));
    return {&p, level};
  }
  throw py::key_error(name + ": no such stage (mrr.stages() lists them; per-level ones as mask.L1)");
}

// mrr.Frame: one frame's options, as `mrr render` takes them, its render and its stages.
class PyFrame {
 public:
  // The frame's options from keyword arguments, through the words `mrr render` parses (frameWords,
  // FrameOptions::add), checked as the command line checks them: a bad one is a ValueError here.
  PyFrame(std::shared_ptr<PyScene> scene, const py::kwargs& kwargs) : scene_(std::move(scene)) {
    py::kwargs params;
    for (const auto& [k, v] : kwargs) {
      if (std::string(py::str(k)) == "masks")
        setMasks(py::reinterpret_borrow<py::object>(v));
      else
        params[k] = v;
    }
    options_.quiet = true;
    // The scene as a word of its own, so that it wins over a frame file's (frame="F.json" is
    // expanded as `mrr render --frame F.json` expands it: the words given win).
    std::vector<std::string> words = {"render", optionName(Param::Scene) + "=" + scene_->name};
    for (std::string& w : frameWords(params)) words.push_back(std::move(w));
    words = expandFrameFile(words);
    words.erase(words.begin());
    CLI::App app;
    options_.add(app);
    std::reverse(words.begin(), words.end());  // CLI11 takes them last first
    try {
      app.parse(words);
    } catch (const CLI::ParseError& e) {
      throw BadValue(e.what());
    }
    options_.checkPath();
    settings_ = options_.settings();
    require(options_.threads >= 0 && options_.threads <= 1024,
            optionName(Param::Threads) + ": must be in " + paramRange(Param::Threads));
    memoryEstimate_ = estimateFrameBytes(makeConstants(settings_, 1.0f), true);
    requireMemory(memoryEstimate_, memoryLimit(options_.memoryLimitGiB),
                  "a " + options_.size + " " + toString(settings_.effect) + " frame");
    loaded_ = scene_->resolve(options_.sceneRequest());
  }

  // A mask rule (a callable taking the frame so far) or a dict of arrays, or None.
  void setMasks(py::object masks) {
    if (!masks.is_none() && !PyCallable_Check(masks.ptr()) && !py::isinstance<py::dict>(masks))
      throw BadValue("masks: expected a callable (the frame so far → a dict of arrays), a dict of arrays, or None");
    masks_ = std::move(masks);
  }

  // Renders the frame as `mrr render` does (the GIL released while the renderer runs); with
  // `reference`, also mode full and the error against it (`render --reference`, SPEC §10).
  PyFrame& render(bool reference) {
    require(masks_.is_none() || options_.path == "cpu",
            "masks: a frame takes masks from Python on the oracle (path cpu) only");
    const PathOptions pathOptions = options_.pathOptions();
    const std::shared_ptr<RendererSlot> slot = loaded_->renderer(options_.path, pathOptions);
    const std::thread::id me = std::this_thread::get_id();
    if (slot->user.load() == me)
      throw BadValue("render: this thread is rendering a frame of this scene already (a mask rule may not render)");
    if (options_.path == "gpu" && slot->maker != me)
      throw PortUnavailable(
          "path gpu: the port's GL context is current on the thread that first rendered this "
          "scene on it; render the scene's gpu frames on that thread");
    FrameRenderer* renderer = slot->renderer.get();
    const Constants constants = makeConstants(settings_, loaded_->rs.framed.size);
    const CostModel costs = options_.costModel(options_.path);
    RenderOptions ro;
    ro.keepStages = true;
    ro.costModel = &costs;
    std::vector<std::string> replaced;
    if (!masks_.is_none()) {
      ro.replaceMasks = [this, &replaced](const FrameResult& f, Masks& masks) {
        py::gil_scoped_acquire gil;  // the rule is Python: the GIL for as long as it runs
        py::object given = masks_;
        if (PyCallable_Check(masks_.ptr())) given = masks_(maskContext(f, masks));
        if (given.is_none()) return;
        if (!py::isinstance<py::dict>(given))
          throw BadValue("masks: the rule returned " + std::string(py::str(py::type::of(given).attr("__name__"))) +
                         ", expected a dict of arrays by stage name (mask.L1, stencil.L2, ...) or None");
        replaced = applyUserMasks(py::reinterpret_borrow<py::dict>(given), f, masks);
      };
    }
    auto frame = std::make_shared<FrameResult>();
    std::optional<FrameErrors> errors;
    FrameHistory previous;  // SPEC §14: the previous frame first, where the temporal term reads one
    {
      py::gil_scoped_release nogil;
      const std::lock_guard<std::mutex> lock(slot->busy);  // another thread's frame of this scene first
      slot->user = me;
      const struct Done {
        std::atomic<std::thread::id>& user;
        ~Done() { user = std::thread::id(); }
      } done{slot->user};
      tbb::global_control gc(tbb::global_control::max_allowed_parallelism,
                             static_cast<size_t>(threadCount(options_.threads)));
      previous = previousFrameHistory(*renderer, loaded_->rs.camera, settings_, loaded_->rs.framed.size, &costs);
      if (!previous.empty()) ro.history = &previous;
      *frame = renderer->render(loaded_->rs.camera, constants, ro);
      if (reference) {
        Settings full = settings_;
        full.mode = Mode::Full;
        RenderOptions plain;  // as `render --reference`: the path's own costs, no stages kept
        plain.keepStages = false;
        const FrameResult ref =
            renderer->render(loaded_->rs.camera, makeConstants(full, loaded_->rs.framed.size), plain);
        errors = errorVsFull(*frame, ref);
      }
    }
    RunInfo info{
        loaded_->rs.scene.name, loaded_->rs.scene.credit, options_.path, threadCount(options_.threads), {}, {}};
    if (options_.path == "gpu") {
      info.renderer = renderer->device();
      info.timingMethod = renderer->timingMethod();
    }
    info.memoryEstimateBytes = memoryEstimate_;
    info.peakResidentBytes = peakResidentBytes();
    report_ = makeReport(*frame, info, errors);
    report_["frame"] = options_.frame(loaded_->rs, settings_);
    if (!masks_.is_none()) report_["masks_from_python"] = replaced;
    frame_ = frame;
    return *this;
  }

  // A stage by name, as a float32 array in its EXR layout (`mrr render --stages`): in place where
  // the frame holds it so (keeping the frame alive), else converted.
  py::array stage(const std::string& name) const {
    const auto [info, level] = parseStage(name);
    const FrameResult& f = rendered();
    const PartImageAccess& access = *info->image;
    if (!access.holds(f, level))
      throw py::key_error(name + ": not in this frame (" + toString(f.constants.mode) + ", " +
                          toString(f.constants.effect) + ": frame.stages() lists what it holds)");
    if (access.view) {
      const ImageF* image = access.view(f, level);
      if (image && !image->empty()) return viewArray(*image, frame_);
    }
    return ownedArray(access.read(f, level));
  }

  // Whether the frame holds the stage `name` (false before it is rendered, and for no stage).
  bool contains(const std::string& name) const {
    if (!frame_) return false;
    try {
      const auto [info, level] = parseStage(name);
      return info->image->holds(*frame_, level);
    } catch (const py::key_error&) {
      return false;
    }
  }

  // Every stage this frame holds, in the stages EXR's order (heldParts).
  std::vector<std::string> stages() const {
    std::vector<std::string> names;
    for (const PartRef& p : heldParts(rendered())) names.push_back(partName(p.part, p.level));
    return names;
  }

  // The report, as `mrr render --report` writes it.
  py::object report() const {
    rendered();
    return toPython(report_);
  }
  // The frame file, as `mrr render --frame-out` writes it (the camera and light as resolved).
  py::object frameFile() const { return toPython(options_.frame(loaded_->rs, settings_)); }
  // Whether render() has run.
  bool isRendered() const { return frame_ != nullptr; }
  // "mrr.Frame(builtin:demo, effect=ssao, method=mrr, size=160x96, path=cpu, rendered)".
  std::string repr() const {
    return "mrr.Frame(" + scene_->name + ", effect=" + toString(settings_.effect) +
           ", method=" + toString(settings_.mode) + ", size=" + std::to_string(settings_.width) + "x" +
           std::to_string(settings_.height) + ", path=" + options_.path + (frame_ ? ", rendered)" : ")");
  }
  // The padded grid (W, H) of level ℓ: the shape a mask or stencil of that level takes.
  std::pair<int, int> levelSize(int level) const {
    if (level < 0 || level >= kLevelCount)
      throw BadValue("level " + std::to_string(level) + ": not in 0.." + std::to_string(kLevelCount - 1));
    const Constants c = makeConstants(settings_, loaded_->rs.framed.size);
    const LevelConstants& lc = c.levels[static_cast<size_t>(level)];
    return {lc.height, lc.width};
  }

 private:
  // The rendered frame; ValueError before render().
  const FrameResult& rendered() const {
    if (!frame_) throw py::value_error("the frame is not rendered yet: call frame.render() first");
    return *frame_;
  }

  std::shared_ptr<PyScene> scene_;
  FrameOptions options_;
  Settings settings_;
  int64_t memoryEstimate_ = 0;
  std::shared_ptr<LoadedScene> loaded_;
  py::object masks_ = py::none();
  std::shared_ptr<const FrameResult> frame_;
  nlohmann::json report_;
};

// Two arrays of one shape, as images (the metrics' arguments).
std::pair<ImageF, ImageF> imagePair(const py::handle& test, const py::handle& ref) {
  ImageF a = imageFromArray(test, "test"), b = imageFromArray(ref, "reference");
  if (a.width != b.width || a.height != b.height || a.channels != b.channels)
    throw BadValue("the images differ in shape: test " + std::to_string(a.height) + "x" + std::to_string(a.width) +
                   "x" + std::to_string(a.channels) + ", reference " + std::to_string(b.height) + "x" +
                   std::to_string(b.width) + "x" + std::to_string(b.channels));
  return {std::move(a), std::move(b)};
}

// A stages EXR part with its channels in the stage list's order (EXR files keep channels sorted by
// name: the G-buffer's depth, P.x, ... come back as N.x, N.y, ...); other parts as the file holds them.
ImageF inStageOrder(ExrPart& part) {
  const PartInfo* info = nullptr;
  int level = -1;
  try {
    std::tie(info, level) = parseStage(part.name);
  } catch (const py::key_error&) {
    return std::move(part.image);
  }
  const std::vector<std::string> order = partChannels(info->part, part.image);
  const size_t n = part.channelNames.size();
  if (order.size() != n) return std::move(part.image);
  std::vector<size_t> from(n);
  for (size_t k = 0; k < n; ++k) {
    const auto at = std::find(part.channelNames.begin(), part.channelNames.end(), order[k]);
    if (at == part.channelNames.end()) return std::move(part.image);
    from[k] = static_cast<size_t>(at - part.channelNames.begin());
  }
  ImageF out(part.image.width, part.image.height, part.image.channels);
  for (size_t p = 0; p < out.pixelCount(); ++p)
    for (size_t k = 0; k < n; ++k) out.data[p * n + k] = part.image.data[p * n + from[k]];
  return out;
}

// A frame-parameter row as a dict, for mrr.params().
py::dict paramDict(const FrameParamInfo& p) {
  static const char* kKinds[] = {"text", "int", "number", "triple", "flag", "levels", "per_level", "switch"};
  py::dict d;
  d["key"] = std::string(p.key);
  d["option"] = optionName(p.param);
  d["kind"] = kKinds[static_cast<int>(p.kind)];
  d["unit"] = std::string(p.unit);
  d["help"] = paramHelp(p.param);
  d["range"] = paramRange(p.param);
  return d;
}

// A stage-list row as a dict, for mrr.stages().
py::dict stageDict(const PartInfo& p) {
  static const char* kGrids[] = {"level", "screen", "tiles", "light"};
  py::dict d;
  d["name"] = std::string(p.name);
  d["per_level"] = p.perLevel;
  d["step"] = p.step;
  d["channels"] = partChannels(p.part, 1);
  d["grid"] = kGrids[static_cast<int>(p.grid)];
  d["what"] = std::string(p.what);
  return d;
}

}  // namespace

}  // namespace mrr::python

using namespace mrr;
using namespace mrr::python;

PYBIND11_MODULE(_mrr, m) {
  m.doc() = "mrr: multi-resolution rendering of expensive lighting effects (docs/python.md)";
  py::register_exception<MrrError>(m, "Error", PyExc_ValueError);
  py::register_exception<PortUnavailable>(m, "PortUnavailable", PyExc_RuntimeError);
  py::register_exception<BadValue>(m, "BadValue", PyExc_ValueError);

  py::class_<PyScene, std::shared_ptr<PyScene>>(m, "Scene", "A loaded scene (mrr.load_scene)")
      .def_readonly("name", &PyScene::name)
      .def_property_readonly("triangles", [](const PyScene& s) { return s.scene().triangleCount(); })
      .def_property_readonly("credit", [](const PyScene& s) { return s.scene().credit; })
      .def("__repr__", [](const PyScene& s) { return "mrr.Scene(" + s.name + ")"; });
  m.def(
      "load_scene", [](const std::string& name) { return std::make_shared<PyScene>(name); }, py::arg("scene"),
      "Loads a scene: 'builtin:demo' (mrr scenes lists them), a shared scene's short name, or a .gltf/.glb path");

  py::class_<PyFrame>(m, "Frame",
                      "Frame(scene, effect='ssao', method='mrr', size=(W, H), masks=None, **params): one frame, "
                      "with the command line's parameters as keyword arguments (mrr.params())")
      .def(py::init<std::shared_ptr<PyScene>, const py::kwargs&>(), py::arg("scene"))
      .def(py::init([](const std::string& name, const py::kwargs& params) {
             return PyFrame(std::make_shared<PyScene>(name), params);  // a scene by name: loaded here
           }),
           py::arg("scene"))
      .def("render", &PyFrame::render, py::arg("reference") = false, py::return_value_policy::reference_internal,
           "Renders the frame as `mrr render` does; reference=True also renders mode full and adds error_vs_full")
      .def("__getitem__", &PyFrame::stage, py::arg("stage"), "A stage by name ('final', 'mask.L1') as float32")
      .def("__contains__", &PyFrame::contains)
      .def("stages", &PyFrame::stages, "The stages this frame holds, by name")
      .def("level_shape", &PyFrame::levelSize, py::arg("level"), "(rows, columns) of level l's padded grid")
      .def_property_readonly("report", &PyFrame::report, "The report, as `mrr render --report` writes it")
      .def_property_readonly("frame_file", &PyFrame::frameFile, "The frame file (`mrr render --frame-out`)")
      .def_property_readonly("rendered", &PyFrame::isRendered)
      .def("__repr__", &PyFrame::repr);

  m.def(
      "methods", [] { return toPython(methodRowsJson()); }, "The method table (mrr methods --json)");
  m.def(
      "params",
      [] {
        py::list rows;
        for (const FrameParamInfo& p : frameParams()) rows.append(paramDict(p));
        return rows;
      },
      "The frame-parameter table: each row's key (the keyword), option, kind, unit, help and range");
  m.def(
      "stages",
      [] {
        py::list rows;
        for (const PartInfo& p : kParts) rows.append(stageDict(p));
        return rows;
      },
      "The stage list: every part's name, whether per level, its channels, grid and what it holds");
  m.def("level_count", [] { return kLevelCount; });

  m.def(
      "rms",
      [](const py::handle& test, const py::handle& ref) {
        const auto [a, b] = imagePair(test, ref);
        return rmsError(a, b);
      },
      py::arg("test"), py::arg("reference"), "RMS error (SPEC §10)");
  m.def(
      "ssim",
      [](const py::handle& test, const py::handle& ref) {
        const auto [a, b] = imagePair(test, ref);
        return ssim(a, b);
      },
      py::arg("test"), py::arg("reference"), "SSIM (SPEC §10: 11x11 Gaussian, sigma 1.5, range 1)");
  m.def(
      "psnr",
      [](const py::handle& test, const py::handle& ref) {
        const auto [a, b] = imagePair(test, ref);
        return psnr(a, b);
      },
      py::arg("test"), py::arg("reference"));
  m.def(
      "flip",
      [](const py::handle& test, const py::handle& ref, std::optional<double> ppd) {
        const auto [a, b] = imagePair(test, ref);
        FlipResult r = flip(b, a, ppd.value_or(kFlipDefaultPpd));
        return py::make_tuple(toPython(nlohmann::json(r.stats)), ownedArray(std::move(r.errorMap)));
      },
      py::arg("test"), py::arg("reference"), py::arg("ppd") = py::none(),
      "LDR-FLIP of display values in [0, 1]: (stats dict, error map)");

  m.def(
      "read_image", [](const std::string& path) { return ownedArray(readImage(path)); }, py::arg("path"),
      "An image file (EXR, PNG) as float32");
  m.def(
      "read_parts",
      [](const std::string& path) {
        py::dict parts;
        for (ExrPart& p : readParts(path)) parts[py::str(p.name)] = ownedArray(inStageOrder(p));
        return parts;
      },
      py::arg("path"),
      "Every part of a multi-part EXR (`mrr render --stages`) by name, as float32, a stage's channels in "
      "the stage list's order");
}
