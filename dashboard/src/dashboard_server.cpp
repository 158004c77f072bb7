#include "dashboard/dashboard_server.hpp"

#include <httplib.h>
#include <spdlog/spdlog.h>

#include <chrono>
#include <fstream>
#include <sstream>
#include <random>

#include "dashboard/guarded_http_server.hpp"
#include "dashboard/message_json.hpp"
#include "planner_core/input_error.hpp"
#include "dashboard/web_assets.hpp"

namespace dashboard {

namespace {

constexpr auto kFrameGap = std::chrono::milliseconds(50);  // at most 20 frames per second per page
constexpr size_t kBytesPerGapMs = 10 * 1024;               // bigger frames come less often: 2 MB, 5 a second
constexpr auto kHeartbeat = std::chrono::seconds(1);       // a frame at least this often
constexpr double kTaskAnswerS = 5;                         // how long a task request waits for the coordinator

// Texts from the fleet or from a request may hold bytes that are not UTF-8: shown replaced, never thrown.
std::string dump(const Json& json) { return json.dump(-1, ' ', false, Json::error_handler_t::replace); }

std::string sse(const std::string& event, const Json& data) { return "event: " + event + "\ndata: " + dump(data) + "\n\n"; }

void reply_json(httplib::Response& response, int status, const Json& body) {
  response.status = status;
  response.set_content(dump(body), "application/json");
}

// An integer field of a request's JSON body, checked in its type (a number such as 1e140 must not
// reach a cast to int).
int integer_field(const Json& body, const char* field) {
  const Json& value = body.at(field);
  if (!value.is_number_integer() || (value.is_number_unsigned() && value.get<uint64_t>() > INT32_MAX) ||
      (!value.is_number_unsigned() && (value.get<int64_t>() < INT32_MIN || value.get<int64_t>() > INT32_MAX))) {
    throw std::invalid_argument(std::string(field) + " must be an integer in [-2147483648, 2147483647]");
  }
  return value.get<int>();
}

// A route's handler: the request has been read whole once it runs.
template <typename Handler>
auto handled(Handler handler) {
  return [handler](const httplib::Request& request, httplib::Response& response) {
    GuardedHttpServer::mark_request_read();
    handler(request, response);
  };
}

}  // namespace

DashboardServer::DashboardServer(double lost_after_s, RequestTask request_task, HistoryRecorder* recorder)
    : http_(std::make_unique<GuardedHttpServer>()),
      request_task_(std::move(request_task)),
      recorder_(recorder),
      now_ms_(fleet_transport::wall_clock_ms),
      view_(lost_after_s) {
  http_->set_exception_handler([](const httplib::Request&, httplib::Response& response, std::exception_ptr) {
    reply_json(response, 500, {{"reason", "internal error"}});
  });
  add_routes();
}

DashboardServer::~DashboardServer() { stop(); }

void DashboardServer::apply(const HistoryEntry& entry) {
  if (recorder_ != nullptr) recorder_->write(entry);
  const std::lock_guard<std::mutex> lock(mutex_);
  dashboard::apply(view_, entry);
  ++changes_;
  changed_.notify_all();
}

void DashboardServer::touch() {
  const std::lock_guard<std::mutex> lock(mutex_);
  ++changes_;
  changed_.notify_all();
}

void DashboardServer::on_task_reply(const fleet_transport::TaskReply& reply) {
  const std::lock_guard<std::mutex> lock(mutex_);
  const auto found = pending_.find(reply.request_id);
  if (found == pending_.end() || found->second) return;  // not ours, or answered already
  found->second = reply;
  answered_.notify_all();
}

fleet_transport::TaskReply DashboardServer::request(fleet_transport::TaskRequest request) {
  {
    const std::lock_guard<std::mutex> lock(mutex_);
    static std::mt19937_64 random{std::random_device{}()};
    request.request_id = "dashboard-" + std::to_string(random() % 1000000000) + "-" + std::to_string(++requests_made_);
    pending_[request.request_id];
  }
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::duration_cast<std::chrono::steady_clock::duration>(
                                                                std::chrono::duration<double>(kTaskAnswerS));
  std::unique_lock<std::mutex> lock(mutex_);
  while (!pending_[request.request_id] && std::chrono::steady_clock::now() < deadline && !stopping_) {
    lock.unlock();
    request_task_(request);  // again every second until answered (the coordinator answers repeats alike)
    lock.lock();
    answered_.wait_until(lock, std::min<std::chrono::steady_clock::time_point>(
                                   deadline, std::chrono::steady_clock::now() + std::chrono::seconds(1)));
  }
  std::optional<fleet_transport::TaskReply> answer = pending_[request.request_id];
  pending_.erase(request.request_id);
  if (answer) return *answer;
  fleet_transport::TaskReply none;
  none.request_id = request.request_id;
  none.reason = "no coordinator answered within " + std::to_string(static_cast<int>(kTaskAnswerS)) + " s";
  return none;
}

Json DashboardServer::frame() const {
  Json frame = view_.frame_json(now_ms_());
  frame["replay"] = static_cast<bool>(set_speed_);
  return frame;
}

void DashboardServer::add_routes() {
  // The page's files: built in, or read from --web-dir at every request (to work on the page
  // without rebuilding). Only the built-in names are served either way.
  const auto serve_file = [this](const std::string& path, const WebAsset& asset, httplib::Response& response) {
    response.set_header("Cache-Control", "no-cache");
    if (web_dir_.empty()) {
      response.set_content(asset.body, asset.content_type);
      return;
    }
    std::ifstream in(web_dir_ + path, std::ios::binary);
    if (!in) {
      response.status = 404;
      response.set_content("not in --web-dir " + web_dir_ + ": " + path, "text/plain");
      return;
    }
    std::ostringstream body;
    body << in.rdbuf();
    response.set_content(body.str(), asset.content_type);
  };
  http_->Get("/", handled([serve_file](const httplib::Request&, httplib::Response& response) {
    serve_file("/index.html", web_assets().at("/index.html"), response);
  }));
  for (const auto& [path, asset] : web_assets()) {
    http_->Get(path, handled([serve_file, path = path, &asset = asset](const httplib::Request&, httplib::Response& response) {
      serve_file(path, asset, response);
    }));
  }
  http_->Get("/api/frame", handled([this](const httplib::Request&, httplib::Response& response) {
    const std::lock_guard<std::mutex> lock(mutex_);
    reply_json(response, 200, frame());
  }));
  http_->Get("/api/mission", handled([this](const httplib::Request&, httplib::Response& response) {
    const std::lock_guard<std::mutex> lock(mutex_);
    reply_json(response, 200, view_.mission_json());
  }));
  http_->Get("/api/plan", handled([this](const httplib::Request&, httplib::Response& response) {
    const std::lock_guard<std::mutex> lock(mutex_);
    reply_json(response, 200, view_.plan_json());
  }));
  http_->Get("/api/stream", handled([this](const httplib::Request&, httplib::Response& response) {
    if (!http_->mark_stream()) {
      response.set_header("Retry-After", "2");
      reply_json(response, 503, {{"reason", "too many event streams open: retry later"}});
      return;
    }
    response.set_header("Cache-Control", "no-cache");
    // Per page: what it has been sent so far.
    auto sent = std::make_shared<std::tuple<int, int, uint64_t>>(-1, -1, ~uint64_t{0});  // mission, plan, changes
    response.set_chunked_content_provider("text/event-stream", [this, sent](size_t, httplib::DataSink& sink) {
      std::string out;
      {
        std::unique_lock<std::mutex> lock(mutex_);
        auto& [mission, plan, changes] = *sent;
        changed_.wait_for(lock, kHeartbeat, [&] { return stopping_ || changes_ != changes; });
        if (stopping_) return false;
        changes = changes_;
        if (view_.mission_version() != mission) {
          mission = view_.mission_version();
          out += sse("mission", view_.mission_json());
        }
        if (view_.plan_version() != plan) {
          plan = view_.plan_version();
          out += sse("plan", view_.plan_json());
        }
        out += sse("frame", frame());
      }
      if (!sink.write(out.data(), out.size())) return false;  // the page went away
      std::this_thread::sleep_for(std::max<std::chrono::milliseconds>(
          kFrameGap, std::chrono::milliseconds(out.size() / kBytesPerGapMs)));
      return true;
    });
  }));
  http_->Post("/api/tasks", handled([this](const httplib::Request& http_request, httplib::Response& response) {
    if (!request_task_) {
      reply_json(response, 409, {{"accepted", false}, {"reason", "a replay: tasks cannot be added to it"}});
      return;
    }
    fleet_transport::TaskRequest request;
    try {
      const Json body = Json::parse(http_request.body);
      const std::string action = body.value("action", "add");
      if (action == "add") {
        request.action = fleet_transport::TaskAction::kAdd;
        request.x = integer_field(body, "x");
        request.y = integer_field(body, "y");
        request.robot_id = body.contains("robot") ? body.at("robot").get<std::string>() : "";
      } else if (action == "cancel") {
        request.action = fleet_transport::TaskAction::kCancel;
        request.task = integer_field(body, "task");
      } else {
        throw std::invalid_argument("action must be add or cancel, not '" + action + "'");
      }
      if (!request.robot_id.empty() && !fleet_transport::is_valid_robot_id(request.robot_id)) {
        throw std::invalid_argument(std::string("not a robot id: robot ids are ") + fleet_transport::kRobotIdRule);
      }
    } catch (const std::exception& e) {
      reply_json(response, 400, {{"accepted", false}, {"reason", std::string("bad request: ") + e.what()}});
      return;
    }
    const fleet_transport::TaskReply reply = this->request(request);
    reply_json(response, 200,
               {{"accepted", reply.accepted}, {"reason", reply.reason}, {"task", reply.task}, {"robot", reply.robot_id}});
  }));
  http_->Post("/api/replay", handled([this](const httplib::Request& http_request, httplib::Response& response) {
    if (!set_speed_) {
      reply_json(response, 409, {{"reason", "not a replay"}});
      return;
    }
    try {
      const double speed = Json::parse(http_request.body).at("speed").get<double>();
      if (!(speed >= 0 && speed <= 1000)) throw std::invalid_argument("speed must be in [0, 1000] (0 pauses)");
      set_speed_(speed);
      touch();
      reply_json(response, 200, {{"speed", speed}});
    } catch (const std::exception& e) {
      reply_json(response, 400, {{"reason", std::string("bad request: ") + e.what()}});
    }
  }));
}

void DashboardServer::bind(const std::string& host, int port) {
  port_ = port == 0 ? http_->bind_to_any_port(host) : (http_->bind_to_port(host, port) ? port : -1);
  if (port_ <= 0) {
    throw planner_core::InputError("--listen " + host + " --port " + std::to_string(port) +
                                   ": cannot listen there (the port is in use, or that is not an address of this host)");
  }
}

void DashboardServer::serve() { http_->listen_after_bind(); }

void DashboardServer::stop() {
  {
    const std::lock_guard<std::mutex> lock(mutex_);
    stopping_ = true;
    changed_.notify_all();
    answered_.notify_all();
  }
  if (http_) {
    http_->stop_connections();
    http_->stop();
  }
}

}  // namespace dashboard
