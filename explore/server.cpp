#include "explore/server.h"

#include <httplib.h>
#include <nlohmann/json.hpp>
#include <tbb/global_control.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <charconv>
#include <chrono>
#include <condition_variable>
#include <deque>
#include <filesystem>
#include <functional>
#include <future>
#include <iostream>
#include <list>
#include <map>
#include <memory>
#include <mutex>
#include <set>
#include <sstream>
#include <thread>

#include <arpa/inet.h>
#include <malloc.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include "common/error.h"
#include "common/frame_params.h"
#include "common/memory.h"
#include "common/paths.h"
#include "common/stages.h"
#include "common/tolerance.h"
#include "compare/metrics/false_colour.h"
#include "compare/parity/noise.h"
#include "compare/parity/probe_both.h"
#include "compare/report/report.h"
#include "cpu_ref/probe.h"
#include "explore/budget.h"
#include "explore/explore_files.h"
#include "explore/layers.h"
#include "gpu/context.h"
#include "frontend/renderers.h"
#include "scenes/builtin.h"
#include "scenes/catalog.h"

namespace mrr::explore {

namespace {

using nlohmann::json;

// A request the API refuses: its status, the reason and the parameter at fault.
struct ApiError {
  int status = 400;
  std::string message;
  std::string parameter;  // empty: none in particular
  json extra = json::object();  // more members of the error's JSON (the budget's figures)
};

// Thrown on the render thread at a stage boundary when the job was cancelled: its client left,
// or a newer request for the same view came. It unwinds the render; nothing half made is cached.
struct Cancelled {
  std::string why;
};

// A render the HTTP threads hand to the render thread.
struct Job {
  std::function<void(const Job&)> body;
  std::string view;  // the page's view it renders for ("" none): a newer one for it supersedes this
  std::string key;   // what it renders: a newer request for the same view and frame does not
  std::promise<void> done;

  void cancel(const std::string& reason) {
    std::lock_guard lock(whyMutex_);
    if (!cancelled_) why_ = reason;
    cancelled_ = true;
  }
  bool cancelled() const { return cancelled_; }
  // At a stage boundary: throws Cancelled if the job was cancelled.
  void check() const {
    if (!cancelled_) return;
    std::lock_guard lock(whyMutex_);
    throw Cancelled{why_};
  }

 private:
  std::atomic<bool> cancelled_{false};
  mutable std::mutex whyMutex_;
  std::string why_;
};

// The socket of a request's connection: cpp-httplib 0.11 (Debian 12) does not hand it to the
// handler, so it is found among this process's descriptors by its two ends. -1: not found.
int connectionSocket(const httplib::Request& req) {
  if (req.remote_port <= 0) return -1;
  std::error_code ec;
  for (const auto& entry : std::filesystem::directory_iterator("/proc/self/fd", ec)) {
    int fd = -1;
    const std::string name = entry.path().filename().string();
    if (std::from_chars(name.data(), name.data() + name.size(), fd).ec != std::errc()) continue;
    sockaddr_storage peer{}, local{};
    socklen_t peerLength = sizeof peer, localLength = sizeof local;
    if (getpeername(fd, reinterpret_cast<sockaddr*>(&peer), &peerLength) != 0) continue;
    if (getsockname(fd, reinterpret_cast<sockaddr*>(&local), &localLength) != 0) continue;
    auto endpoint = [](const sockaddr_storage& a) -> std::pair<std::string, int> {
      char text[INET6_ADDRSTRLEN] = {};
      if (a.ss_family == AF_INET) {
        const auto& v4 = reinterpret_cast<const sockaddr_in&>(a);
        inet_ntop(AF_INET, &v4.sin_addr, text, sizeof text);
        return {text, ntohs(v4.sin_port)};
      }
      if (a.ss_family == AF_INET6) {
        const auto& v6 = reinterpret_cast<const sockaddr_in6&>(a);
        inet_ntop(AF_INET6, &v6.sin6_addr, text, sizeof text);
        return {text, ntohs(v6.sin6_port)};
      }
      return {"", -1};
    };
    const auto [peerAddress, peerPort] = endpoint(peer);
    const auto [localAddress, localPort] = endpoint(local);
    if (peerPort == req.remote_port && peerAddress == req.remote_addr &&
        (req.local_port <= 0 || localPort == req.local_port))
      return fd;
  }
  return -1;
}

// Whether the client at the other end of `fd` has gone: it closed or reset the connection. (A
// browser sends nothing more on a connection while it waits for the answer, and closes it when
// the page aborts the request.)
bool clientLeft(int fd) {
  pollfd p{fd, static_cast<short>(POLLIN | POLLRDHUP), 0};
  if (poll(&p, 1, 0) <= 0) return false;
  if (p.revents & (POLLHUP | POLLERR | POLLRDHUP | POLLNVAL)) return true;
  if (p.revents & POLLIN) {
    char c = 0;
    return recv(fd, &c, 1, MSG_PEEK | MSG_DONTWAIT) == 0;
  }
  return false;
}

// What a waiting request watches: its connection, and the page's view it renders for.
struct Watch {
  const httplib::Request* request = nullptr;
  std::string view;
};

// The frame parameters the page may send are the frame-parameter table's rows marked for
// explore (common/frame_params.h): the command line's frame options, '-' as '_'. Options that
// name files (--cost-model) or the machine (--threads, --gl-device, --memory-limit) stay on the
// command line. Flags take 1/true or 0/false.
const FrameParamInfo* pageParameter(const std::string& key) {
  std::string option = "--" + key;
  std::replace(option.begin(), option.end(), '_', '-');
  const FrameParamInfo* p = findParam(option);  // the option or an alias: "mode" is --method's
  return p && p->explore ? p : nullptr;
}

// "--tau-n 3: must be in [0, 2]" → "tau_n": the first option an error message names.
std::string parameterNamed(const std::string& message) {
  const size_t at = message.find("--");
  if (at == std::string::npos) return {};
  size_t end = at + 2;
  while (end < message.size() && (std::isalnum(static_cast<unsigned char>(message[end])) || message[end] == '-')) ++end;
  std::string name = message.substr(at + 2, end - at - 2);
  std::replace(name.begin(), name.end(), '-', '_');
  return name;
}

const char* kindName(ParamKind kind) {
  switch (kind) {
    case ParamKind::Text: return "text";
    case ParamKind::Int: return "int";
    case ParamKind::Number: return "number";
    case ParamKind::Triple: return "triple";
    case ParamKind::Flag: return "flag";
    case ParamKind::Levels: return "levels";
    case ParamKind::PerLevel: return "per_level";
    case ParamKind::Switch: return "switch";
  }
  return "text";
}

json vec3Json(const glm::vec3& v) { return json::array({v.x, v.y, v.z}); }

// What one request asks to render, resolved and checked.
struct FrameRequest {
  FrameOptions options;
  Settings settings;
  SceneRequest scene;
  std::string sceneKey;      // what loading the scene depends on
  std::string key;           // the frame (path aside)
  std::string referenceKey;  // its full-resolution reference
  double work = 0.0;         // estimated, in sample-pixels (explore/budget.h)
  int mostSamples = 0;       // the most samples within the budget at this frame's other settings
};

// A frame's cache key: its frame file (FrameOptions::frame: every row that says which frame to
// render, so a new parameter is in the key as soon as it is in the table) and the scene request
// (the camera and light as asked, before the scene resolves them).
std::string frameKey(const FrameOptions& fo, const Settings& s, const SceneRequest& r) {
  auto opt = [](const auto& o) { return o ? json(*o) : json(nullptr); };
  auto optVec = [](const std::optional<glm::vec3>& v) { return v ? vec3Json(*v) : json(nullptr); };
  const json request = json::array({r.scene, opt(r.flipUp), opt(r.cameraIndex), optVec(r.eye), optVec(r.target),
                                    optVec(r.up), opt(r.fovDegrees), optVec(r.lightToward), r.skipBlendMaterials});
  // The motion term's previous camera, which the frame file names only as a file.
  const FoveationSettings& f = s.foveation;
  const json previous = json::array({f.motion, vec3Json(f.prevEye), vec3Json(f.prevTarget), vec3Json(f.prevUp), f.prevYfov});
  return fo.frame(nullptr, s).dump() + request.dump() + previous.dump();
}

// The full-resolution frame a frame is measured against: mode full, and nothing that only
// chooses which pixels the method shades. The sampling seed is the frame's (SPEC §7.1): the
// reference of a seeded frame draws the same samples, as render --reference's does.
Settings referenceSettings(const Settings& s) {
  Settings r = defaultSettings(s.effect);
  r.width = s.width;
  r.height = s.height;
  r.seed = s.seed;
  r.ssao = s.ssao;
  r.ssm = s.ssm;
  r.ssgi = s.ssgi;
  r.bilateral = s.bilateral;
  r.mode = Mode::Full;
  r.neverSlower = false;
  return r;
}

// A rendered frame, kept in the cache; read-only once made, from any thread.
struct Rendered {
  int64_t bytes = 0;  // estimateFrameBytes of the frame, for the cache's budget
  FrameResult frame;
  json report;
  std::shared_ptr<const Rendered> reference;  // null for a reference itself
  double wallMs = 0.0;
};
using RenderedPtr = std::shared_ptr<const Rendered>;

// The scene being shown, its renderers and their GL context: touched by the render thread only.
struct SceneState {
  std::string key;
  std::unique_ptr<Scene> scene;
  std::map<std::string, std::unique_ptr<FrameRenderer>> renderers;  // by path; the port's made on first use
  std::set<std::string> warm;              // the paths that have rendered here (shaders compiled, scratch paged in)
};

class Explorer {
 public:
  explicit Explorer(const ServerOptions& options)
      : options_(options), cacheBudget_(memoryLimit(options.frame.memoryLimitGiB).bytes / 2),
        budget_(options.budget * 1e6) {
    for (const std::string& n : builtinSceneNames()) scenes_.push_back("builtin:" + n);
    for (const SharedSceneInfo& s : sharedSceneCatalog())  // those this machine has
      if (std::filesystem::exists(std::filesystem::path(sharedScenesDir()) / s.file)) scenes_.push_back(s.name);
    if (std::find(scenes_.begin(), scenes_.end(), options.frame.scene) == scenes_.end())
      scenes_.push_back(options.frame.scene);  // the scene named on the command line
    worker_ = std::thread([this] { workLoop(); });
    // The port's status, found on the thread that will own its context.
    runOnWorker([this](const Job&) {
      try {
        const gpu::GlContext context(options_.frame.glDevice);
        portAvailable_ = true;
        portStatus_ = "available";
      } catch (const std::exception& e) {
        portStatus_ = e.what();
      }
    });
  }
  ~Explorer() {
    {
      std::lock_guard lock(queueMutex_);
      stopping_ = true;
    }
    queueReady_.notify_all();
    worker_.join();
  }

  // The request's frame parameters, checked; `endpoint`: the parameters the endpoint itself takes.
  FrameRequest parse(const httplib::Request& req, const std::set<std::string>& endpoint) const {
    std::vector<std::string> args;
    for (const auto& [key, value] : req.params) {
      if (endpoint.count(key)) continue;
      const FrameParamInfo* p = pageParameter(key);
      if (!p) throw ApiError{400, "unknown parameter " + key, key};
      if (p->kind == ParamKind::Flag) {
        if (value == "0" || value == "false") continue;
        if (!(value.empty() || value == "1" || value == "true"))
          throw ApiError{400, key + "=" + value + ": a flag takes 1, true, 0 or false", key};
        args.push_back(optionName(p->param));
        continue;
      }
      args.push_back(optionName(p->param) + "=" + value);
    }
    FrameRequest r;
    r.options = options_.frame;
    if (!args.empty()) {
      CLI::App app;
      r.options.add(app);
      std::reverse(args.begin(), args.end());  // CLI11 takes them last first
      try {
        app.parse(args);
      } catch (const CLI::ParseError& e) {
        throw ApiError{400, e.what(), parameterNamed(e.what())};
      }
    }
    if (std::find(scenes_.begin(), scenes_.end(), r.options.scene) == scenes_.end())
      throw ApiError{400,
                     "scene " + r.options.scene +
                         ": not offered (a built-in, a shared scene, or the scene given on the command line)",
                     "scene"};
    try {
      r.settings = r.options.settings();
      r.scene = r.options.sceneRequest();
      // Three frames of this size may be kept per path: the frame, its reference, a neighbour.
      requireMemory(3 * estimateFrameBytes(makeConstants(r.settings, 1.0f), true),
                    memoryLimit(options_.frame.memoryLimitGiB), "a " + r.options.size + " frame");
    } catch (const MrrError& e) {
      // the page cannot raise the memory limit: a frame too large is its size's fault
      const bool memory = std::string(e.what()).find("over the memory limit") != std::string::npos;
      std::string parameter = memory ? std::string(paramInfo(Param::Size).key) : parameterNamed(e.what());
      throw ApiError{400, e.what(), parameter};
    }
    checkBudget(r);
    SceneRequest sceneOnly = r.scene;
    sceneOnly.eye = sceneOnly.target = std::nullopt;
    sceneOnly.cameraIndex = std::nullopt;
    sceneOnly.fovDegrees = std::nullopt;
    r.sceneKey = frameKey(FrameOptions{}, defaultSettings(Effect::Ssao), sceneOnly);
    r.key = frameKey(r.options, r.settings, r.scene);
    r.referenceKey = frameKey(r.options, referenceSettings(r.settings), r.scene);
    return r;
  }

  // A request whose estimated work is over the budget is a 400 naming the parameter
  // to lower (samples when fewer would fit, else the shadow map's size or the frame's size) and the
  // budget, with the figures for the page: budget_m, work_m (millions of sample-pixels) and
  // max_samples (the most that fit at this size; 0: none).
  void checkBudget(FrameRequest& r) const {
    const Settings& s = r.settings;
    const WorkLine line = requestWork(s, referenceSettings(s));
    r.work = line.at(s.samples());
    r.mostSamples = mostSamplesWithin(line, budget_, s.effect);
    if (r.work <= budget_) return;
    const auto key = [](Param p) { return std::string(paramInfo(p).key); };
    std::string parameter = key(Param::Samples), advice;
    if (r.mostSamples > 0) {
      advice = "at most " + std::to_string(r.mostSamples) + " samples fit at this size";
    } else {
      Settings smaller = s;
      smaller.ssm.shadowMapSize = defaultSettings(s.effect).ssm.shadowMapSize;
      const bool shadowMap = s.effect != Effect::Ssao && smaller.ssm.shadowMapSize < s.ssm.shadowMapSize &&
                             requestWork(smaller, referenceSettings(smaller)).at(1) <= budget_;
      parameter = key(shadowMap ? Param::ShadowMapSize : Param::Size);
      advice = shadowMap ? "even 1 sample is over it with this shadow map: choose a smaller shadow_map_size"
                         : "even 1 sample is over it at this size: choose a smaller size";
    }
    throw ApiError{400,
                   r.options.size + ", " + toString(s.effect) + ", " + std::to_string(s.samples()) + " samples, " +
                       toString(s.mode) + ": an estimated " + millions(r.work) +
                       " M sample-pixels of work (the frame and its full-resolution reference), over this server's "
                       "budget of " + millions(budget_) + " M (mrr explore --budget); " + advice,
                   parameter,
                   {{"budget_m", budget_ / 1e6}, {"work_m", r.work / 1e6}, {"max_samples", r.mostSamples}}};
  }

  static std::string millions(double work) {
    char text[32];
    const double m = work / 1e6;
    std::snprintf(text, sizeof text, m >= 100.0 ? "%.0f" : "%.3g", m);
    return text;
  }

  static std::string pathParameter(const httplib::Request& req, bool bothAllowed) {
    const std::string path = req.has_param("path") ? req.get_param_value("path") : "cpu";
    if (path == "cpu" || path == "gpu" || (bothAllowed && path == "both")) return path;
    throw ApiError{400, "path " + path + ": expected cpu or gpu" + std::string(bothAllowed ? ", or both" : ""), "path"};
  }

  // The frame on `path`, from the cache or rendered (one at a time, on the render thread). While
  // it waits, the request's connection is watched: when its client leaves, the render is cancelled
  // and the request returns at once; a newer request for the same view cancels it too (409).
  RenderedPtr frame(const FrameRequest& r, const std::string& path, const Watch& watch = {}) {
    if (path == "gpu" && !portAvailable_)
      throw ApiError{503, "the port is unavailable here: " + portStatus_, "path"};
    if (RenderedPtr hit = cached("frame " + path + r.key)) return hit;
    // The job owns what it reads: its request may be gone before it runs.
    auto out = std::make_shared<RenderedPtr>();
    runOnWorker([this, r, path, out](const Job& job) { *out = renderOnWorker(r, path, job); }, watch,
                path + r.key);
    return *out;
  }

  // The oracle's stochastic stages over kNoiseRule.seeds independent seeds for the
  // request's frame (compare --noise-aware's reference), rendered one seed after another on the
  // render thread ("oracle: noise-aware seed k/K" in /api/progress), cancelled as a frame is, and
  // kept for the last kCachedNoise frames. Bounded: the seeds' estimated work may be at most
  // kNoiseBudgetRequests requests' budget (400 naming size or samples otherwise).
  struct Noise {
    std::shared_ptr<const NoiseReference> reference;
    double seconds = 0.0;  // what rendering the seeds took (0 when cached)
    bool cached = false;
  };
  Noise noise(const FrameRequest& r, const Watch& watch = {}) {
    checkNoiseBudget(r);
    const std::string key = "noise " + r.key;
    if (auto hit = cachedNoise(key)) return {hit, 0.0, true};
    auto out = std::make_shared<Noise>();
    runOnWorker([this, r, key, out](const Job& job) { *out = noiseOnWorker(r, key, job); }, watch, key);
    return *out;
  }

  void checkNoiseBudget(const FrameRequest& r) const {
    const Settings& s = r.settings;
    const double work = kNoiseRule.seeds * frameWork(s).at(s.samples()), most = kNoiseBudgetRequests * budget_;
    if (work <= most) return;
    const auto key = [](Param p) { return std::string(paramInfo(p).key); };
    const bool fewer = kNoiseRule.seeds * frameWork(s).at(1.0) <= most;
    throw ApiError{400,
                   "noise-aware: the oracle's " + std::to_string(kNoiseRule.seeds) + " seeds of this frame are an "
                       "estimated " + millions(work) + " M sample-pixels of work, over " +
                       millions(kNoiseBudgetRequests * 1e6) + " x this server's budget (" + millions(most) +
                       " M); choose " + (fewer ? "fewer samples" : "a smaller size"),
                   key(fewer ? Param::Samples : Param::Size),
                   {{"budget_m", most / 1e6}, {"work_m", work / 1e6}}};
  }

  // Loads the command line's scene and builds its BVH before the first request: a scene that
  // cannot be read is one line and exit 2, not a page that fails.
  void preload() {
    const FrameRequest r = parse(httplib::Request{}, {});
    runOnWorker([&](const Job&) { sceneFor(r); });
  }

  json info() const {
    json parts = json::array();
    for (const PartInfo& p : kParts)
      parts.push_back({{"name", p.name}, {"per_level", p.perLevel}, {"step", p.step}, {"what", p.what}});
    const auto key = [](Param p) { return std::string(paramInfo(p).key); };
    json defaults = {{key(Param::Scene), options_.frame.scene},
                     {key(Param::Effect), options_.frame.effect},
                     {key(Param::Method), toString(parseMode(options_.frame.mode))},  // its row's name
                     {key(Param::Size), options_.frame.size}};
    if (options_.frame.samples) defaults[key(Param::Samples)] = *options_.frame.samples;
    const Settings s = options_.frame.settings();
    defaults[key(Param::TauN)] = s.edges.normalThreshold;
    defaults[key(Param::TauZ)] = s.edges.depthThreshold;
    defaults[key(Param::NeverSlower)] = paramText(s, Param::NeverSlower);
    // The page's knobs and their help: the table's rows the page may send.
    json params = json::array();
    for (const FrameParamInfo& p : frameParams())
      if (p.explore)
        params.push_back({{"key", p.key}, {"option", optionName(p.param)}, {"kind", kindName(p.kind)},
                          {"unit", p.unit}, {"help", paramHelp(p.param)}, {"range", paramRange(p.param)}});
    // The page's methods, from the method table (common/methods.h): its menu and which knobs each owns.
    const json methodRows = methodRowsJson();
    return {{"scenes", scenes_},
            {"budget",
             {{"budget_m", budget_ / 1e6},
              {"unit", "millions of sample-pixels (one SSAO sample at one pixel, about 8 ns on 2 cores)"},
              {"what", "a request's estimated work (its frame and the full-resolution reference) may not exceed "
                       "this; mrr explore --budget sets it"}}},
            {"port", {{"available", portAvailable_}, {"status", portStatus_}, {"renderer", portRenderer()}}},
            {"defaults", defaults},
            {"params", params},
            {"methods", methodRows},
            {"parts", parts},
            {"probe_relative_difference", kProbeRelativeDifference},
            {"teach", teachSteps()}};
  }

  json progress() const {
    std::lock_guard lock(progressMutex_);
    return {{"busy", busy_},
            {"job", job_},
            {"stage", stage_},
            {"queued", queued_},
            {"renders", renders_},
            {"cancelled", cancelled_},
            {"elapsed_ms", busy_ ? std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - started_).count()
                                 : 0.0}};
  }

  std::string portRenderer() const {
    std::lock_guard lock(progressMutex_);
    return portRenderer_;
  }

 private:
  void workLoop() {
    for (;;) {
      std::shared_ptr<Job> job;
      {
        std::unique_lock lock(queueMutex_);
        queueReady_.wait(lock, [&] { return stopping_ || !queue_.empty(); });
        if (queue_.empty()) return;
        job = std::move(queue_.front());
        queue_.pop_front();
      }
      try {
        job->check();  // cancelled while it queued: not started
        job->body(*job);
        job->done.set_value();
      } catch (...) {
        job->done.set_exception(std::current_exception());
      }
      if (job->cancelled()) {
        std::lock_guard lock(progressMutex_);
        ++cancelled_;
      }
      job.reset();
      // A frame's images are large and short-lived: give what the render freed back to the
      // system, so that the server's memory is its cache's, not the peak of every frame it made.
      malloc_trim(0);
    }
  }

  // Runs `body` on the render thread and waits for it; its exception comes back here. With a
  // watch: a newer job for the same view and another frame cancels this one (409), and when the
  // request's client leaves, this one is cancelled and the wait ends at once.
  void runOnWorker(std::function<void(const Job&)> body, const Watch& watch = {}, const std::string& key = {}) {
    auto job = std::make_shared<Job>();
    job->body = std::move(body);
    job->view = watch.view;
    job->key = key;
    std::future<void> done = job->done.get_future();
    {
      std::lock_guard lock(queueMutex_);
      if (!job->view.empty()) {
        for (auto it = views_.begin(); it != views_.end();)  // the views of finished jobs
          it = it->second.expired() ? views_.erase(it) : std::next(it);
        std::weak_ptr<Job>& latest = views_[job->view];
        if (const std::shared_ptr<Job> older = latest.lock(); older && older->key != job->key)
          older->cancel("superseded by a newer request for view " + job->view);
        latest = job;
      }
      queue_.push_back(job);
    }
    {
      std::lock_guard lock(progressMutex_);
      ++queued_;
    }
    queueReady_.notify_one();
    struct Dequeued {
      Explorer* self;
      ~Dequeued() {
        std::lock_guard lock(self->progressMutex_);
        --self->queued_;
      }
    } dequeued{this};
    const int fd = watch.request ? connectionSocket(*watch.request) : -1;
    while (done.wait_for(std::chrono::milliseconds(50)) != std::future_status::ready) {
      if (fd >= 0 && clientLeft(fd)) {
        job->cancel("the client left");
        throw ApiError{503, "the client left; its render is cancelled", {}};
      }
      if (job->cancelled()) break;  // superseded: the render thread skips it, or stops it at a stage boundary
    }
    if (done.wait_for(std::chrono::seconds(0)) != std::future_status::ready)
      throw ApiError{409, "superseded by a newer request for view " + job->view, "view"};
    try {
      done.get();
    } catch (const Cancelled& c) {
      throw ApiError{409, c.why, job->view.empty() ? std::string() : "view"};
    }
  }

  RenderedPtr cached(const std::string& key) {
    std::lock_guard lock(cacheMutex_);
    for (auto it = cache_.begin(); it != cache_.end(); ++it)
      if (it->first == key) {
        cache_.splice(cache_.begin(), cache_, it);  // most recently used first
        return it->second;
      }
    return nullptr;
  }

  // Keeps the newest frames: at most kCachedFrames, and within half the memory limit (the two
  // newest always). Frames still in use live on in their shared_ptr.
  void remember(const std::string& key, RenderedPtr frame) {
    std::lock_guard lock(cacheMutex_);
    cache_.emplace_front(key, std::move(frame));
    const int64_t budget = cacheBudget_;
    auto total = [&] {
      int64_t sum = 0;
      for (const auto& entry : cache_) sum += entry.second->bytes;
      return sum;
    };
    while (cache_.size() > kCachedFrames || (cache_.size() > 2 && total() > budget)) cache_.pop_back();
  }

  void setProgress(const std::string& job, const std::string& stage) {
    std::lock_guard lock(progressMutex_);
    if (!job.empty()) job_ = job;
    stage_ = stage;
  }

  SceneState& sceneFor(const FrameRequest& r) {
    if (state_.key == r.sceneKey && state_.scene) return state_;
    setProgress("loading " + r.scene.scene, "scene");
    state_ = SceneState{};  // the old renderers and their GL context go first
    SceneRequest load = r.scene;
    state_.scene = std::make_unique<Scene>(loadRequestedScene(load));
    setProgress("", "building the BVH");
    state_.renderers["cpu"] = makeRenderer("cpu", *state_.scene);
    state_.key = r.sceneKey;
    return state_;
  }

  // The render thread's progress while it works: busy from construction to destruction (the
  // progress endpoint's elapsed time counts from `start`); a frame counts in renders_.
  struct Busy {
    Explorer& self;
    bool countsAsRender;
    Busy(Explorer& s, std::chrono::steady_clock::time_point start, bool counts) : self(s), countsAsRender(counts) {
      std::lock_guard lock(self.progressMutex_);
      self.busy_ = true;
      self.started_ = start;
    }
    Busy(const Busy&) = delete;
    Busy& operator=(const Busy&) = delete;
    ~Busy() {
      std::lock_guard lock(self.progressMutex_);
      self.busy_ = false;
      self.stage_.clear();
      if (countsAsRender) ++self.renders_;
    }
  };

  // Cancellation: `job` is checked before each render and at every stage boundary
  // (the progress hook the driver calls as each stage starts), where Cancelled unwinds the render.
  // The cache only ever takes whole frames, after they are made: a cancelled render leaves the
  // cache as it was, but for a reference it finished before it was cancelled.
  RenderedPtr renderOnWorker(const FrameRequest& r, const std::string& path, const Job& job) {
    if (RenderedPtr hit = cached("frame " + path + r.key)) return hit;  // rendered while this one queued
    const auto start = std::chrono::steady_clock::now();
    const Busy busy(*this, start, /*countsAsRender=*/true);
    SceneState& state = sceneFor(r);
    std::unique_ptr<FrameRenderer>& renderer = state.renderers[path];
    if (!renderer) {
      setProgress("", "making the GL context");
      renderer = makeRenderer(path, *state.scene, options_.frame.pathOptions());
      std::lock_guard lock(progressMutex_);
      portRenderer_ = renderer->device();
    }
    const Camera camera = requestedCamera(r.scene, *state.scene);
    // The automatic radii from what this view frames, as render resolves them (the same frame, the same bits).
    const float framed = framedSize(*state.scene, camera, r.scene.aspect).size;
    // Both paths take the oracle's never-slower costs, as compare does: the same decision.
    const CostModel costs = options_.frame.costModel("cpu");
    const std::string who = path == "cpu" ? "oracle" : "port";
    auto render = [&](const Constants& k, bool keepStages, const std::string& what) {
      // A stage's start ("raw.L0") is a boundary; its tenths ("raw.L0 40%", from the oracle's
      // parallel loops, maybe on another thread) only report.
      const ProgressFn progress = [this, &job](const std::string& stage) {
        if (stage.find('%') == std::string::npos) job.check();
        setProgress("", stage);
      };
      job.check();
      setProgress(who + ": " + what, "");
      // The rule's samples with it off too (explore's default): the page shows what it would decide.
      return renderer->render(camera, k, {keepStages, progress, &costs, /*sampleWithRuleOff=*/true});
    };
    // A renderer's first frames pay for compiling shaders and paging in scratch: one throwaway
    // frame of each kind first, so the measured speedup compares warm frames. One sample each:
    // the samples are a uniform, not part of the shaders, and cost no paging.
    if (!state.warm.count(path)) {
      Settings warm = r.settings;
      warm.setSamples(1);
      render(makeConstants(referenceSettings(warm), framed), false, "warming up (full resolution)");
      render(makeConstants(warm, framed), false, "warming up");
      state.warm.insert(path);
    }
    job.check();
    RenderedPtr reference = cached("reference " + path + r.referenceKey);
    if (!reference) {
      auto ref = std::make_shared<Rendered>();
      const Constants full = makeConstants(referenceSettings(r.settings), framed);
      ref->bytes = estimateFrameBytes(full, false);
      ref->frame = render(full, false, "full-resolution reference");
      reference = ref;
      remember("reference " + path + r.referenceKey, reference);
    }
    auto out = std::make_shared<Rendered>();
    const Constants constants = makeConstants(r.settings, framed);
    out->frame = render(constants, true,
                        toString(r.settings.mode) + " " + toString(r.settings.effect) + " " + r.options.size);
    out->reference = reference;
    out->bytes = estimateFrameBytes(constants, true);
    RunInfo info{state.scene->name, state.scene->credit, path, tbb::this_task_arena::max_concurrency(), {}, {}};
    if (path == "gpu") {
      info.renderer = renderer->device();
      info.timingMethod = renderer->timingMethod();
    }
    info.memoryEstimateBytes = estimateFrameBytes(constants, true);
    info.peakResidentBytes = peakResidentBytes();
    out->report = makeReport(out->frame, info, errorVsFull(out->frame, reference->frame));
    const double frameMs = out->frame.timing(timedName(Timed::Total)), fullMs = reference->frame.timing(timedName(Timed::Total));
    out->wallMs = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    out->report["explore"] = {
        {"full_ms", fullMs},
        {"frame_ms", frameMs},
        {"measured_speedup", frameMs > 0.0 ? fullMs / frameMs : 0.0},
        {"render_wall_ms", out->wallMs},
        {"layers", layerNames(out->frame, true)},
        {"key", r.key},
        {"work_m", r.work / 1e6},
        {"budget_m", budget_ / 1e6},
        {"max_samples", r.mostSamples}};
    const FallbackDecision& rule = out->frame.fallback;
    if (methodInfo(r.settings.mode).neverSlower && !rule.evaluated)  // the rule is off: what it would have decided
      out->report["explore"]["rule_off"] = {{"would_fall_back", rule.wouldFallBack},
                                            {"predicted_full_ms", rule.predictedFullMs},
                                            {"predicted_mrr_ms", rule.predictedMrrMs}};
    remember("frame " + path + r.key, out);
    return out;
  }

  std::shared_ptr<const NoiseReference> cachedNoise(const std::string& key) {
    std::lock_guard lock(cacheMutex_);
    for (auto it = noiseCache_.begin(); it != noiseCache_.end(); ++it)
      if (it->first == key) {
        noiseCache_.splice(noiseCache_.begin(), noiseCache_, it);
        return it->second;
      }
    return nullptr;
  }

  Noise noiseOnWorker(const FrameRequest& r, const std::string& key, const Job& job) {
    if (auto hit = cachedNoise(key)) return {hit, 0.0, true};  // made while this one queued
    const auto start = std::chrono::steady_clock::now();
    const Busy busy(*this, start, /*countsAsRender=*/false);
    SceneState& state = sceneFor(r);
    FrameRenderer& oracle = *state.renderers.at("cpu");
    const Camera camera = requestedCamera(r.scene, *state.scene);
    const float framed = framedSize(*state.scene, camera, r.scene.aspect).size;
    const CostModel costs = options_.frame.costModel("cpu");
    const ProgressFn progress = [this, &job](const std::string& stage) {
      if (stage.find('%') == std::string::npos) job.check();
      setProgress("", stage);
    };
    Settings seeded = r.settings;
    auto reference = std::make_shared<NoiseReference>(buildNoiseReference(
        [&](uint32_t seed) {
          job.check();
          seeded.seed = seed;
          return oracle.render(camera, makeConstants(seeded, framed), {true, progress, &costs, /*sampleWithRuleOff=*/true});
        },
        makeConstants(r.settings, framed).samples(), [&](int k, int n) {
          setProgress("oracle: noise-aware seed " + std::to_string(k + 1) + "/" + std::to_string(n), "");
        }));
    {
      std::lock_guard lock(cacheMutex_);
      noiseCache_.emplace_front(key, reference);
      while (noiseCache_.size() > kCachedNoise) noiseCache_.pop_back();
    }
    return {reference, std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(), false};
  }

  // docs/method.md's paragraphs marked `<!-- teach: part ... -->`, per stage in pipeline order.
  static json teachSteps() {
    std::string method;
    for (const ExploreFile& f : kExploreFiles)
      if (std::string(f.path) == "docs/method.md") method = f.text;
    std::map<std::string, std::string> text;
    std::map<std::string, std::string> heading;
    std::istringstream lines(method);
    std::string line, section;
    std::vector<std::string> marked;
    bool inParagraph = false;
    for (std::string l; std::getline(lines, l);) {
      if (l.rfind("## ", 0) == 0) section = l.substr(3);
      if (l.rfind("<!-- teach:", 0) == 0) {
        std::istringstream words(l.substr(11));
        marked.clear();
        for (std::string w; words >> w && w != "-->";) marked.push_back(w);
        inParagraph = false;
        continue;
      }
      const bool blank = l.find_first_not_of(" \t") == std::string::npos;
      if (blank) {
        if (inParagraph) marked.clear();
        inParagraph = false;
        continue;
      }
      if (marked.empty() || l.rfind("![", 0) == 0 || l.rfind("|", 0) == 0) continue;
      inParagraph = true;
      for (const std::string& part : marked) {
        std::string& t = text[part];
        t += (t.empty() || t.back() == '\n' ? "" : " ") + l;
        if (!heading.count(part)) heading[part] = section;
      }
    }
    json steps = json::array();
    auto add = [&](const std::string& part, const std::string& what) {
      steps.push_back({{"part", part}, {"what", what}, {"section", heading[part]}, {"text", text[part]}});
    };
    for (const PartInfo& p : kParts) add(std::string(p.name), std::string(p.what));
    add("difference", "the difference from the full-resolution frame");
    add("flip", "the perceptual difference (LDR-FLIP) from the full-resolution frame");
    return steps;
  }

  static constexpr size_t kCachedFrames = 12;
  static constexpr size_t kCachedNoise = 2;  // noise references (K frames' stochastic stages each)

  ServerOptions options_;
  int64_t cacheBudget_ = 0;
  double budget_ = 0.0;  // a request's most work, in sample-pixels (explore/budget.h)
  std::vector<std::string> scenes_;
  bool portAvailable_ = false;  // set once, before any request
  std::string portStatus_;

  std::thread worker_;
  std::mutex queueMutex_;
  std::condition_variable queueReady_;
  std::deque<std::shared_ptr<Job>> queue_;
  std::map<std::string, std::weak_ptr<Job>> views_;  // the newest job of each view
  bool stopping_ = false;
  SceneState state_;  // render thread only

  std::mutex cacheMutex_;
  std::list<std::pair<std::string, RenderedPtr>> cache_;
  std::list<std::pair<std::string, std::shared_ptr<const NoiseReference>>> noiseCache_;

  mutable std::mutex progressMutex_;
  bool busy_ = false;
  std::string job_, stage_, portRenderer_;
  int queued_ = 0;
  long long renders_ = 0;
  long long cancelled_ = 0;
  std::chrono::steady_clock::time_point started_;
};

void sendJson(httplib::Response& res, const json& j, int status = 200) {
  res.status = status;
  res.set_header("Cache-Control", "no-store");
  res.set_content(j.dump(), "application/json");
}

void sendError(httplib::Response& res, const ApiError& e) {
  json body = {{"error", e.message}, {"parameter", e.parameter.empty() ? json(nullptr) : json(e.parameter)}};
  body.update(e.extra);
  sendJson(res, body, e.status);
}

int intParameter(const httplib::Request& req, const std::string& name, int lo, int hi) {
  if (!req.has_param(name)) throw ApiError{400, name + ": required", name};
  const std::string text = req.get_param_value(name);
  int v = 0;
  const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), v);
  if (ec != std::errc() || end != text.data() + text.size() || v < lo || v > hi)
    throw ApiError{400, name + " " + text + ": expected a whole number in [" + std::to_string(lo) + ", " +
                            std::to_string(hi) + "]",
                   name};
  return v;
}

float gainParameter(const httplib::Request& req) {
  if (!req.has_param("gain")) return 10.0f;
  const std::string text = req.get_param_value("gain");
  try {
    size_t used = 0;
    const float g = std::stof(text, &used);
    if (used == text.size() && std::isfinite(g) && g >= 1.0f && g <= 1000.0f) return g;
  } catch (const std::exception&) {
  }
  throw ApiError{400, "gain " + text + ": expected a number in [1, 1000]", "gain"};
}

// Wraps a handler: ApiError and MrrError become JSON errors, nothing escapes.
httplib::Server::Handler guarded(std::function<void(const httplib::Request&, httplib::Response&)> body) {
  return [body = std::move(body)](const httplib::Request& req, httplib::Response& res) {
    try {
      body(req, res);
    } catch (const ApiError& e) {
      sendError(res, e);
    } catch (const MrrError& e) {
      sendError(res, {400, e.what(), parameterNamed(e.what())});
    } catch (const std::bad_alloc&) {
      sendError(res, {503, "out of memory", {}});
    } catch (const std::exception& e) {
      sendError(res, {500, e.what(), {}});
    }
  };
}

// Who may ask. A page on another site can reach this server through the browser: with
// an image tag (a simple GET, which starts a render), or by DNS rebinding (its own name resolving
// to 127.0.0.1, so that it may read the answers). So a request must name this server in its Host
// (421 otherwise: a rebound name is not one of ours) and, when the browser says where it comes
// from (Sec-Fetch-Site, Origin), come from this server's own page (403 otherwise). No answer
// carries CORS headers, so no other origin may read one.
class HostGuard {
 public:
  HostGuard(const std::string& host, int port) : port_(port) {
    const std::string p = ":" + std::to_string(port);
    wildcard_ = host == "0.0.0.0" || host == "::" || host.empty();
    for (const std::string& name : {std::string("127.0.0.1"), std::string("localhost"), std::string("[::1]")})
      allowed_.insert(name + p);
    allowed_.insert((host.find(':') != std::string::npos ? "[" + host + "]" : lower(host)) + p);
    if (port == 80)  // a browser leaves the default port out
      for (const std::string& a : std::set<std::string>(allowed_)) allowed_.insert(a.substr(0, a.size() - p.size()));
  }

  // The refusal, or an empty ApiError (status 0) when the request may go on.
  ApiError check(const httplib::Request& req) const {
    const std::string host = lower(req.get_header_value("Host"));
    if (!allows(host))
      return {421, "Host " + (host.empty() ? std::string("(none)") : host) +
                       ": this server answers to its own address only (" + *allowed_.begin() + ", ...)",
              {}};
    const std::string site = req.get_header_value("Sec-Fetch-Site");
    if (!site.empty() && site != "same-origin" && site != "none")
      return {403, "Sec-Fetch-Site " + site + ": this server answers its own page only", {}};
    const std::string origin = lower(req.get_header_value("Origin"));
    if (!origin.empty() && origin != "http://" + host)
      return {403, "Origin " + origin + ": this server answers its own page only", {}};
    return {0, {}, {}};
  }

 private:
  static std::string lower(std::string s) {
    std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return std::tolower(c); });
    return s;
  }
  bool allows(const std::string& host) const {
    if (allowed_.count(host)) return true;
    if (!wildcard_) return false;
    // Listening on every address: an address literal with this port (a DNS name could be rebound).
    const std::string p = ":" + std::to_string(port_);
    if (host.size() <= p.size() || host.compare(host.size() - p.size(), p.size(), p) != 0) return false;
    std::string name = host.substr(0, host.size() - p.size());
    unsigned char buffer[sizeof(in6_addr)];
    if (name.size() > 2 && name.front() == '[' && name.back() == ']')
      return inet_pton(AF_INET6, name.substr(1, name.size() - 2).c_str(), buffer) == 1;
    return inet_pton(AF_INET, name.c_str(), buffer) == 1;
  }

  int port_;
  bool wildcard_ = false;
  std::set<std::string> allowed_;
};

const ExploreFile* pageFile(const std::string& name) {
  for (const ExploreFile& f : kExploreFiles)
    if (std::string(f.path) == name) return &f;
  return nullptr;
}

}  // namespace

int serve(const ServerOptions& options) {
  tbb::global_control threads(tbb::global_control::max_allowed_parallelism,
                              static_cast<size_t>(options.frame.threads > 0 ? options.frame.threads
                                                                            : tbb::info::default_concurrency()));
  require(options.port >= 0 && options.port <= 65535, "--port " + std::to_string(options.port) + ": must be in [0, 65535]");
  require(std::isfinite(options.budget) && options.budget > 0.0,
          "--budget " + std::to_string(options.budget) + ": must be a positive number (millions of sample-pixels)");
  require(options.frame.threads >= 0 && options.frame.threads <= 1024, optionName(Param::Threads) + ": must be in " + paramRange(Param::Threads));
  options.frame.checkPath();
  options.frame.settings();        // a bad option is one line and exit 2, before anything serves
  options.frame.sceneRequest();
  options.frame.costModel("cpu");
  {
    const SceneRequest r = options.frame.sceneRequest();
    if (r.scene.rfind("builtin:", 0) == 0) makeBuiltinScene(r.scene.substr(8));  // an unknown name fails here
  }

  httplib::Server server;
  // SO_REUSEADDR only: httplib's default SO_REUSEPORT would let a second server share a port
  // that is in use, where the user must hear that it is.
  server.set_socket_options([](socket_t sock) {
    int yes = 1;
    setsockopt(sock, SOL_SOCKET, SO_REUSEADDR, &yes, sizeof yes);
  });
  int port = options.port;
  if (port == 0) {
    port = server.bind_to_any_port(options.host);
    require(port > 0, "--host " + options.host + ": cannot listen there");
  } else {
    require(server.bind_to_port(options.host, port),
            "--port " + std::to_string(port) + ": cannot listen on " + options.host + ":" + std::to_string(port) +
                " (in use, or the address is not this machine's)");
  }
  Explorer explorer(options);
  try {
    explorer.preload();
  } catch (const ApiError& e) {
    if (e.extra.contains("budget_m")) throw MrrError("--budget: the starting frame is over it: " + e.message);
    throw MrrError(e.message);
  }

  const HostGuard guard(options.host, port);
  server.set_pre_routing_handler([&guard](const httplib::Request& req, httplib::Response& res) {
    const ApiError refused = guard.check(req);
    if (refused.status == 0) return httplib::Server::HandlerResponse::Unhandled;
    sendError(res, refused);
    return httplib::Server::HandlerResponse::Handled;
  });

  for (const char* file : {"index.html", "explore.js", "explore.css"}) {
    const ExploreFile* f = pageFile(std::string("page/") + file);
    require(f != nullptr, std::string("the page's ") + file + " is not built in");
    const std::string type = std::string(file).find(".js") != std::string::npos    ? "text/javascript"
                             : std::string(file).find(".css") != std::string::npos ? "text/css"
                                                                                   : "text/html; charset=utf-8";
    const std::string route = std::string(file) == "index.html" ? "/" : std::string("/") + file;
    server.Get(route, [f, type](const httplib::Request&, httplib::Response& res) {
      res.set_header("Cache-Control", "no-store");
      res.set_content(f->text, type);
    });
  }
  server.Get("/api/info", guarded([&](const httplib::Request&, httplib::Response& res) { sendJson(res, explorer.info()); }));
  server.Get("/api/progress",
             guarded([&](const httplib::Request&, httplib::Response& res) { sendJson(res, explorer.progress()); }));
  server.Get("/api/frame", guarded([&](const httplib::Request& req, httplib::Response& res) {
               const FrameRequest r = explorer.parse(req, {"path", "view"});
               const std::string path = Explorer::pathParameter(req, false);
               const std::string view = req.has_param("view") ? req.get_param_value("view") : "";
               if (view.size() > 64) throw ApiError{400, "view: at most 64 characters", "view"};
               sendJson(res, explorer.frame(r, path, {&req, view.empty() ? view : view + " " + path})->report);
             }));
  server.Get(R"(/api/stage/([A-Za-z0-9_.]+)\.(png|json))",
             guarded([&](const httplib::Request& req, httplib::Response& res) {
               const std::string name = req.matches[1], format = req.matches[2];
               const FrameRequest r = explorer.parse(req, {"path", "gain"});
               const std::string path = Explorer::pathParameter(req, true);
               const float gain = gainParameter(req);
               auto layerOf = [&](const std::string& p) {
                 const RenderedPtr f = explorer.frame(r, p, {&req, {}});
                 const std::vector<std::string> names = layerNames(f->frame, f->reference != nullptr);
                 if (std::find(names.begin(), names.end(), name) == names.end())
                   throw ApiError{404, "no layer " + name + " in this frame (GET /api/frame lists them)", {}};
                 return makeLayer(f->frame, name, f->reference ? &f->reference->frame : nullptr, gain);
               };
               if (path != "both") {
                 const LayerImage layer = layerOf(path);
                 if (format == "json") return sendJson(res, layerMeta(layer));
                 res.set_header("Cache-Control", "no-store");
                 return res.set_content(encodePng(colourise(layer)), "image/png");
               }
               // both: |port − oracle| as a heat map, full scale the largest difference
               const LayerImage oracle = layerOf("cpu"), ported = layerOf("gpu");
               float largest = 0.0f;
               const ImageF delta = layerDifference(oracle, ported, &largest);
               if (delta.empty()) throw ApiError{409, "the paths' " + name + " differ in size", {}};
               const float scale = oracle.kind == LayerKind::Binary || largest <= 0.0f ? 1.0f : largest;
               if (format == "json") {
                 long long differing = 0;
                 for (const float d : delta.data) differing += d > 0.0f;
                 json meta = layerMeta(oracle);
                 meta["kind"] = "difference";
                 meta["lo"] = 0.0;
                 meta["hi"] = scale;
                 meta["largest"] = largest;
                 meta["differing_pixels"] = differing;
                 char full[32];
                 std::snprintf(full, sizeof full, "%.4g", scale);
                 meta["caption"] = "|port - oracle|, max over channels, on the ramp: black 0, full scale " +
                                   std::string(full) +
                                   (oracle.kind == LayerKind::Binary ? " (a mismatch)" : " (the largest here)");
                 return sendJson(res, meta);
               }
               res.set_header("Cache-Control", "no-store");
               res.set_content(encodePng(heatMap(delta, scale)), "image/png");
             }));
  server.Get("/api/value", guarded([&](const httplib::Request& req, httplib::Response& res) {
               const FrameRequest r = explorer.parse(req, {"path", "layer", "x", "y", "gain"});
               const std::string path = Explorer::pathParameter(req, false);
               if (!req.has_param("layer")) throw ApiError{400, "layer: required", "layer"};
               const std::string name = req.get_param_value("layer");
               const int x = intParameter(req, "x", 0, r.settings.width - 1);
               const int y = intParameter(req, "y", 0, r.settings.height - 1);
               const RenderedPtr f = explorer.frame(r, path, {&req, {}});
               const std::vector<std::string> names = layerNames(f->frame, f->reference != nullptr);
               if (std::find(names.begin(), names.end(), name) == names.end())
                 throw ApiError{404, "no layer " + name + " in this frame", "layer"};
               sendJson(res, layerValueAt(makeLayer(f->frame, name, f->reference ? &f->reference->frame : nullptr, gainParameter(req)), x, y));
             }));
  server.Get("/api/probe", guarded([&](const httplib::Request& req, httplib::Response& res) {
               const FrameRequest r = explorer.parse(req, {"path", "x", "y"});
               const std::string path = Explorer::pathParameter(req, true);
               const int x = intParameter(req, "x", 0, r.settings.width - 1);
               const int y = intParameter(req, "y", 0, r.settings.height - 1);
               if (path != "both") return sendJson(res, probePixel(explorer.frame(r, path, {&req, {}})->frame, x, y));
               const RenderedPtr o = explorer.frame(r, "cpu", {&req, {}}), p = explorer.frame(r, "gpu", {&req, {}});
               sendJson(res, probeBothJson(probePixel(o->frame, x, y), probePixel(p->frame, x, y)));
             }));
  // The probe's stochastic stages at a pixel against the oracle's independent seeds
  // (compare --noise-aware's numbers): the subject is the frame on `path` (both: the port).
  server.Get("/api/noise", guarded([&](const httplib::Request& req, httplib::Response& res) {
               const FrameRequest r = explorer.parse(req, {"path", "x", "y"});
               const std::string path = Explorer::pathParameter(req, true);
               const int x = intParameter(req, "x", 0, r.settings.width - 1);
               const int y = intParameter(req, "y", 0, r.settings.height - 1);
               if (!isStochastic(r.settings.effect))
                 throw ApiError{400, "effect " + toString(r.settings.effect) +
                                         ": no stochastic stage (its PCF grid is exact); noise-aware is for ssao and ssgi",
                                std::string(paramInfo(Param::Effect).key)};
               const RenderedPtr o = explorer.frame(r, "cpu", {&req, {}});
               const RenderedPtr subject = path == "cpu" ? o : explorer.frame(r, "gpu", {&req, {}});
               const Explorer::Noise noise = explorer.noise(r, {&req, {}});
               json j = noisePixelJson(noisePixel(o->frame, subject->frame, *noise.reference, x, y));
               j["subject"] = path == "cpu" ? "the oracle's frame at --seed " + std::to_string(r.settings.seed)
                                            : "the port (" + explorer.portRenderer() + ")";
               j["path"] = path == "both" ? "gpu" : path;
               j["reference_seconds"] = noise.seconds;
               j["reference_cached"] = noise.cached;
               sendJson(res, j);
             }));
  server.set_error_handler([](const httplib::Request& req, httplib::Response& res) {
    if (!res.body.empty()) return;  // a handler's own error
    const std::string what = res.status == 404 ? "not found: " : "refused (" + std::to_string(res.status) + "): ";
    sendJson(res, {{"error", what + req.method + " " + req.path}, {"parameter", nullptr}}, res.status);
  });
  server.set_exception_handler([](const httplib::Request&, httplib::Response& res, std::exception_ptr) {
    sendJson(res, {{"error", "internal error"}, {"parameter", nullptr}}, 500);
  });

  std::cerr << "mrr explore: serving http://" << options.host << ":" << port << "/ (Ctrl-C stops)" << std::endl;
  require(server.listen_after_bind(), "--port " + std::to_string(port) + ": the server stopped");
  return 0;
}

}  // namespace mrr::explore
