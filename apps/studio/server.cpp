#include "server.h"

#include <algorithm>
#include <atomic>
#include <charconv>
#include <chrono>
#include <cmath>
#include <exception>
#include <memory>
#include <mutex>
#include <new>
#include <stdexcept>
#include <system_error>
#include <thread>
#include <utility>

#include <httplib.h>
#include <nlohmann/json.hpp>

#include "jobs.h"
#include "meshing.h"
#include "mesohex/core/error.h"
#include "mesohex/stages/medial_import.h"
#include "mesohex/surface/radius_from_surface.h"
#include "mesohex/surface/skeletonize.h"
#include "mesohex_io/medial_io.h"
#include "mesohex_io/skeleton_io.h"
#include "sessions.h"

namespace mesohex::studio {

namespace {

using nlohmann::json;
using Req = httplib::Request;
using Res = httplib::Response;

// An answer other than 200, raised inside a handler.
struct HttpError : std::runtime_error {
    HttpError(int status, std::string code, const std::string& message, ElementRef where = {})
        : std::runtime_error(message), status(status), code(std::move(code)), where(where) {}
    int status;
    std::string code;
    ElementRef where;
};

const char* code_name(ErrorCode c) {
    switch (c) {
        case ErrorCode::InvalidInput: return "InvalidInput";
        case ErrorCode::UnsupportedConfiguration: return "UnsupportedConfiguration";
        case ErrorCode::IoError: return "IoError";
        case ErrorCode::NumericalFailure: return "NumericalFailure";
    }
    return "NumericalFailure";
}

json where_json(const ElementRef& where) {
    const char* kind = "none";
    switch (where.kind) {
        case ElementRef::Kind::FileLine: kind = "line"; break;
        case ElementRef::Kind::SkeletonVertex: kind = "skeleton_vertex"; break;
        case ElementRef::Kind::SkeletonEdge: kind = "skeleton_edge"; break;
        case ElementRef::Kind::SkeletonFace: kind = "skeleton_face"; break;
        default: break;
    }
    json j = {{"kind", kind}};
    if (where.kind != ElementRef::Kind::None && where.index >= 0) j["index"] = where.index;
    return j;
}

json error_json(const std::string& code, const std::string& message, const ElementRef& where = {}) {
    return {{"code", code}, {"message", message}, {"where", where_json(where)}};
}

// A library error after the input was read (analysis, meshing): 422, numerical failures 500.
HttpError library_error(const Error& e) {
    const int status = e.code() == ErrorCode::NumericalFailure ? 500 : 422;
    return HttpError(status, code_name(e.code()), e.what(), e.where());
}

// Any exception -> (status, error JSON).
std::pair<int, json> describe(std::exception_ptr ep) {
    try {
        std::rethrow_exception(ep);
    } catch (const HttpError& e) {
        return {e.status, error_json(e.code, e.what(), e.where)};
    } catch (const Error& e) {
        const HttpError h = library_error(e);
        return {h.status, error_json(h.code, h.what(), h.where)};
    } catch (const JobCancelled& e) {
        return {409, error_json("Cancelled", e.what())};
    } catch (const json::exception& e) {
        return {400, error_json("BadRequest", std::string("malformed JSON: ") + e.what())};
    } catch (const std::invalid_argument& e) {
        return {400, error_json("BadRequest", e.what())};
    } catch (const std::bad_alloc&) {
        return {500, error_json("NumericalFailure", "out of memory")};
    } catch (const std::exception& e) {
        return {500, error_json("NumericalFailure", std::string("internal error: ") + e.what())};
    } catch (...) {
        return {500, error_json("NumericalFailure", "internal error")};
    }
}

void send_json(httplib::Response& res, const std::string& body, int status = 200) {
    res.status = status;
    res.set_content(body, "application/json");
}

void send_error(httplib::Response& res, std::exception_ptr ep) {
    const auto [status, error] = describe(ep);
    send_json(res, json{{"error", error}}.dump(-1, ' ', false, kUtf8Replace), status);
}

const char* status_code_name(int status) {
    switch (status) {
        case 400: return "BadRequest";
        case 403: return "Forbidden";
        case 404: return "NotFound";
        case 409: return "Busy";
        case 413: return "PayloadTooLarge";
        default: return status >= 500 ? "NumericalFailure" : "BadRequest";
    }
}

// Every handler runs inside this: any exception becomes a JSON error.
template <typename F>
httplib::Server::Handler guarded(F f) {
    return [f](const httplib::Request& req, httplib::Response& res) {
        try {
            f(req, res);
        } catch (...) {
            send_error(res, std::current_exception());
        }
    };
}

// POST handlers read the body themselves (a content reader): no form decoding of the body whatever its content type
// (httplib would parse an x-www-form-urlencoded body into query parameters and cap it at 8 KiB), and the size limit
// also holds for chunked bodies, which carry no Content-Length. F(request, body, response).
template <typename F>
httplib::Server::HandlerWithContentReader with_body(std::size_t max_bytes, F f) {
    return [max_bytes, f](const httplib::Request& req, httplib::Response& res, const httplib::ContentReader& reader) {
        try {
            std::string body;
            bool too_large = false;
            bool ok = false;
            // No Content-Length and not chunked: no body (RFC 9112, 6.3); httplib would wait for the connection to
            // close (`curl -X POST` without data).
            if (!req.has_header("Content-Length") &&
                req.get_header_value("Transfer-Encoding").find("chunked") == std::string::npos) {
                f(req, body, res);
                return;
            }
            if (req.is_multipart_form_data()) {
                reader([](const httplib::MultipartFormData&) { return true; },
                       [](const char*, std::size_t) { return true; });
                throw HttpError(400, "BadRequest", "multipart bodies are not read: send the file's text as the body");
            }
            ok = reader([&](const char* data, std::size_t n) {
                if (body.size() + n > max_bytes) {
                    too_large = true;
                    return false;
                }
                body.append(data, n);
                return true;
            });
            if (too_large || res.status == 413)
                throw HttpError(413, "PayloadTooLarge",
                                "request body over the size limit (" + std::to_string(max_bytes) + " bytes)");
            if (!ok) throw HttpError(400, "BadRequest", "could not read the request body");
            f(req, body, res);
        } catch (...) {
            send_error(res, std::current_exception());
        }
    };
}

// A required integer query parameter in [0, 2^53) (a revision number).
long long integer_param(const httplib::Request& req, const char* name) {
    const std::string text = req.has_param(name) ? req.get_param_value(name) : "";
    long long value = -1;
    const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), value);
    if (text.empty() || ec != std::errc() || end != text.data() + text.size() || value < 0 ||
        value > 9007199254740991LL)
        throw HttpError(400, "BadRequest",
                        std::string(name) + " must be an integer from 0 to 2^53 - 1, not '" + text + "'");
    return value;
}

std::string format_param(const httplib::Request& req, const char* fallback = "obj") {
    return req.has_param("format") ? req.get_param_value("format") : fallback;
}

// The request body as a skeleton file's text: a read error is a malformed request (400) naming the line.
Skeleton body_skeleton(const httplib::Request& req, const std::string& body) {
    try {
        return read_skeleton_text(body, format_param(req), "request body");
    } catch (const Error& e) {
        throw HttpError(400, code_name(e.code()), e.what(), e.where());
    }
}

json body_json(const std::string& body) {
    try {
        return json::parse(body);
    } catch (const json::exception& e) {
        throw HttpError(400, "BadRequest", std::string("malformed JSON body: ") + e.what());
    }
}

std::string job_json(const JobSnapshot& s, bool with_result) {
    std::string out = json{{"job", s.id},
                           {"state", to_string(s.state)},
                           {"progress",
                            {{"stage", s.progress.stage},
                             {"step", s.progress.step},
                             {"steps", s.progress.steps},
                             {"sj_min", s.progress.sj_min},
                             {"inverted", s.progress.inverted},
                             {"what", s.progress.what}}}}
                          .dump(-1, ' ', false, kUtf8Replace);
    out.pop_back();  // '}'
    if (with_result && s.state == JobState::Done) out += ",\"result\":" + s.result;
    if (s.state == JobState::Failed) out += ",\"error\":" + s.error;
    out += '}';
    return out;
}

bool finished(JobState s) { return s == JobState::Done || s == JobState::Failed || s == JobState::Cancelled; }

}  // namespace

struct StudioServer::Impl {
    StudioSession session;
    StaticFiles files;
    StudioOptions options;
    std::optional<Domain> domain;
    std::string session_body;  // GET /api/session, built once
    httplib::Server http;
    JobManager jobs;
    std::mutex auto_mutex;
    std::optional<std::string> auto_body;  // /api/auto-skeleton, computed once
    std::mutex save_mutex;
    MeshSessions sessions{static_cast<std::size_t>(std::max(1, options.mesh_sessions))};
    int port = -1;
    std::thread thread;
    std::atomic<bool> stopping{false};

    Impl(StudioSession s, StaticFiles f, StudioOptions o)
        : session(std::move(s)),
          files(std::move(f)),
          options(std::move(o)),
          jobs([](std::exception_ptr ep) { return describe(ep).second.dump(-1, ' ', false, kUtf8Replace); },
               JobLimits{std::max(1, options.kept_jobs_per_client), 64, 32}) {
        if (session.domain) {
            domain.emplace();
            domain->name = session.domain_name;
            domain->surface = std::move(*session.domain);  // the session's copy is not needed any more
            session.domain.reset();
            domain->query.emplace(domain->surface);
        }
        session_body = build_session();
        routes();
    }

    const Domain* domain_ptr() const { return domain ? &*domain : nullptr; }

    const Domain& require_domain(const char* what) const {
        if (!domain)
            throw HttpError(409, "BadRequest", std::string(what) + " needs a domain: start the studio with --surface");
        return *domain;
    }

    std::string build_session() const {
        json j;
        j["skeleton"] = session.skeleton ? skeleton_json(*session.skeleton) : json(nullptr);
        j["skeleton_name"] = session.skeleton ? json(session.skeleton_name) : json(nullptr);
        if (domain) {
            std::vector<double> vertices;
            vertices.reserve(3 * domain->surface.points.size());
            for (const Vec3& p : domain->surface.points) vertices.insert(vertices.end(), {p.x, p.y, p.z});
            std::vector<int> triangles;
            triangles.reserve(3 * domain->surface.triangles.size());
            for (const auto& t : domain->surface.triangles) triangles.insert(triangles.end(), t.begin(), t.end());
            j["domain"] = {{"name", domain->name},
                           {"vertices", vertices},
                           {"triangles", triangles},
                           {"bbox_diagonal", domain->query->bbox_diagonal()}};
        } else {
            j["domain"] = nullptr;
        }
        j["save_target"] = session.save_target.empty() ? json(nullptr) : json(session.save_target);
        j["medial"] = session.medial ? skeleton_json(*session.medial) : json(nullptr);
        return j.dump(-1, ' ', false, kUtf8Replace);
    }

    void routes();
    void mesh_routes();
    void job_routes();
    void edit_routes();
    void static_routes();
    template <typename F>
    httplib::Server::HandlerWithContentReader post_handler(F f) const {
        return with_body(options.max_body_bytes, f);
    }
};

void StudioServer::Impl::routes() {
    http.set_payload_max_length(options.max_body_bytes);
    // No Nagle delay: an answer goes out as its header and then its body (two writes); with Nagle the body's last
    // partial segment waits for the client's (delayed) acknowledgement of the earlier ones.
    http.set_tcp_nodelay(true);
    // No compression: answers travel over loopback, where compressing saves nothing and costs a lot (httplib picks
    // brotli at its top quality when the client accepts it: 20 s for the 2.6 MB body of a 10 k-hex raw mesh on a busy
    // 2-core machine; gzip 0.4 s). The request is httplib's own (non-const) object, handed to us as const.
    http.set_pre_routing_handler([](const httplib::Request& req, httplib::Response&) {
        const_cast<httplib::Request&>(req).headers.erase("Accept-Encoding");
        return httplib::Server::HandlerResponse::Unhandled;
    });
    http.set_exception_handler(
        [](const httplib::Request&, httplib::Response& res, std::exception_ptr ep) { send_error(res, ep); });
    // Errors raised by httplib itself (no route, body too large, bad request line) get a JSON body too.
    http.set_error_handler([](const httplib::Request& req, httplib::Response& res) {
        if (!res.body.empty()) return;
        std::string message = "HTTP " + std::to_string(res.status);
        if (res.status == 404) message = "no such resource: " + req.method + " " + req.path;
        if (res.status == 413) message = "request body over the size limit";
        send_json(res,
                  json{{"error", error_json(status_code_name(res.status), message)}}.dump(-1, ' ', false, kUtf8Replace),
                  res.status);
    });

    mesh_routes();
    job_routes();
    edit_routes();
    static_routes();
}

// The session, the analysis and the raw / final mesh of a skeleton the page sends.
void StudioServer::Impl::mesh_routes() {
    http.Get("/api/session",
             guarded([this](const httplib::Request&, httplib::Response& res) { send_json(res, session_body); }));

    http.Post("/api/analyze", post_handler([this](const Req& req, const std::string& body, Res& res) {
                  const Skeleton s = body_skeleton(req, body);
                  // The analysis and repairs /api/mesh makes: it refuses what /api/mesh refuses, no more.
                  SkeletonAnalysis an;
                  try {
                      an = prepare_for_mesh(s, domain_ptr()).input_analysis;
                  } catch (const Error& e) {
                      throw library_error(e);
                  }
                  try {
                      send_json(res, analyze_response(s, domain_ptr()).dump(-1, ' ', false, kUtf8Replace));
                  } catch (const Error& e) {
                      // The analysis holds but the mesh cannot be built: the error, with the classes for the page.
                      const HttpError h = library_error(e);
                      send_json(
                          res,
                          json{{"error", error_json(h.code, h.what(), h.where)}, {"analysis", analysis_json(an)}}.dump(
                              -1, ' ', false, kUtf8Replace),
                          h.status);
                  }
              }));

    http.Post("/api/mesh", post_handler([this](const Req& req, const std::string& body, Res& res) {
                  const std::string stage = req.has_param("stage") ? req.get_param_value("stage") : "raw";
                  if (stage != "raw" && stage != "final")
                      throw HttpError(400, "BadRequest", "stage must be raw or final, not '" + stage + "'");
                  const bool delta = format_param(req) == "delta";
                  if ((req.has_param("session") || delta) && stage != "raw")
                      throw HttpError(400, "BadRequest", "session and format=delta: stage=raw only");
                  if (stage == "final") require_domain("stage=final");
                  const std::string encoding = req.has_param("encoding") ? req.get_param_value("encoding") : "json";
                  if (encoding != "json" && encoding != "binary")
                      throw HttpError(400, "BadRequest", "encoding must be json or binary, not '" + encoding + "'");
                  // An editing session (raw meshes only): the server keeps the skeleton and what its raw mesh left,
                  // so the next request may send a delta (format=delta) and is remeshed incrementally.
                  std::shared_ptr<MeshSession> ms;
                  std::unique_lock<std::mutex> session_lock;
                  long long revision = -1;
                  long long since = -1;  // the revision of the session's answer the reader holds (-1: none)
                  if (req.has_param("session") || delta) {
                      const std::string id = req.has_param("session") ? req.get_param_value("session") : "";
                      if (!valid_session_id(id))
                          throw HttpError(400, "BadRequest",
                                          "session must be 1 to 64 characters of [A-Za-z0-9._-] (format=delta needs "
                                          "one)");
                      revision = integer_param(req, "revision");
                      if (req.has_param("since")) since = integer_param(req, "since");
                      if (delta) {
                          const long long base = integer_param(req, "base");
                          ms = sessions.find(id);
                          if (ms) session_lock = std::unique_lock<std::mutex>(ms->mutex);
                          if (!ms || !ms->has_skeleton || ms->revision != base)
                              throw HttpError(409, "SendFullSkeleton",
                                              !ms || !ms->has_skeleton
                                                  ? "unknown session '" + id +
                                                        "' (never started, or dropped for newer ones): send the full "
                                                        "skeleton"
                                                  : "the session holds revision " + std::to_string(ms->revision) +
                                                        ", not " + std::to_string(base) + ": send the full skeleton");
                      } else {
                          ms = sessions.find_or_create(id);
                          session_lock = std::unique_lock<std::mutex>(ms->mutex);
                      }
                  }
                  const auto t0 = std::chrono::steady_clock::now();
                  Skeleton s;
                  if (delta) {
                      try {
                          s = apply_skeleton_delta(ms->skeleton, body);
                      } catch (const Error& e) {
                          throw HttpError(400, code_name(e.code()), e.what(), e.where());
                      }
                  } else {
                      s = body_skeleton(req, body);
                  }
                  if (ms) {  // the session's skeleton is now this one, meshed or not
                      ms->skeleton = s;
                      ms->revision = revision;
                      ms->has_skeleton = true;
                  }
                  MeshRequest request;
                  request.parse_ms =
                      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
                  request.finish = stage == "final";
                  request.encoding = encoding == "binary" ? Encoding::Binary : Encoding::Json;
                  // since=R: the reader holds the session's answer of revision R; a binary answer then patches it.
                  BinaryArrays kept;
                  if (ms && request.encoding == Encoding::Binary) {
                      request.arrays_out = &kept;
                      if (since >= 0 && since == ms->answer_revision) {
                          request.patch_base = &ms->answer;
                          request.patch_of = ms->answer_revision;
                      }
                  }
                  try {
                      std::string answer = mesh_response(s, domain_ptr(), request, nullptr, ms ? &ms->cache : nullptr);
                      if (request.arrays_out) {
                          ms->answer = std::move(kept);
                          ms->answer_revision = revision;
                      }
                      if (request.encoding == Encoding::Binary) {
                          res.status = 200;
                          res.set_content(std::move(answer), "application/octet-stream");
                      } else {
                          send_json(res, answer);
                      }
                  } catch (const Error& e) {
                      throw library_error(e);
                  }
              }));
}

// Finishing jobs: start, poll, cancel, and their progress as server-sent events.
void StudioServer::Impl::job_routes() {
    http.Post("/api/jobs", post_handler([this](const Req& req, const std::string& body, Res& res) {
                  const Domain& d = require_domain("a finishing job");
                  std::string client =
                      req.has_header("X-Studio-Client") ? req.get_header_value("X-Studio-Client") : "default";
                  if (client.empty() || client.size() > 200)
                      throw HttpError(400, "BadRequest", "X-Studio-Client: 1 to 200 characters");
                  Skeleton s = body_skeleton(req, body);
                  const Domain* dp = &d;
                  const std::optional<long> id = jobs.submit(client, [s = std::move(s), dp](JobContext& ctx) {
                      MeshRequest request;
                      request.finish = true;
                      request.progress = [&ctx](const MeshProgress& p) {
                          ctx.progress({p.stage, p.step, p.steps, p.sj_min, p.inverted, p.what});
                      };
                      return mesh_response(s, dp, request);
                  });
                  if (!id) throw HttpError(409, "Busy", "too many jobs waiting; try again later");
                  send_json(res, json{{"job", *id}}.dump(-1, ' ', false, kUtf8Replace), 202);
              }));

    http.Get(R"(/api/jobs/(\d{1,15}))", guarded([this](const httplib::Request& req, httplib::Response& res) {
                 const long id = std::stol(req.matches[1].str());
                 const std::optional<JobSnapshot> s = jobs.get(id);
                 if (!s) throw HttpError(404, "NotFound", "no job " + std::to_string(id) + " (unknown or dropped)");
                 send_json(res, job_json(*s, true));
             }));

    http.Delete(R"(/api/jobs/(\d{1,15}))", guarded([this](const httplib::Request& req, httplib::Response& res) {
                    const long id = std::stol(req.matches[1].str());
                    if (!jobs.cancel(id))
                        throw HttpError(404, "NotFound", "no job " + std::to_string(id) + " (unknown or dropped)");
                    send_json(res, job_json(*jobs.get(id), false));
                }));

    // Server-sent events: one "data: {job, state, progress}" event per change, until the job is finished.
    http.Get(R"(/api/jobs/(\d{1,15})/events)", guarded([this](const httplib::Request& req, httplib::Response& res) {
                 const long id = std::stol(req.matches[1].str());
                 if (!jobs.get(id))
                     throw HttpError(404, "NotFound", "no job " + std::to_string(id) + " (unknown or dropped)");
                 res.set_header("Cache-Control", "no-cache");
                 auto seen = std::make_shared<long>(-1);
                 res.set_chunked_content_provider("text/event-stream", [this, id, seen](std::size_t,
                                                                                        httplib::DataSink& sink) {
                     if (stopping.load() || !sink.is_writable()) return false;
                     const std::optional<JobSnapshot> s = jobs.wait_change(id, *seen, std::chrono::milliseconds(500));
                     if (!s) {
                         sink.done();
                         return true;
                     }
                     if (s->version != *seen) {
                         *seen = s->version;
                         const std::string event = "data: " + job_json(*s, false) + "\n\n";
                         if (!sink.write(event.data(), event.size())) return false;
                     }
                     if (finished(s->state)) sink.done();
                     return true;
                 });
             }));
}

// Skeleton editing helpers: automatic skeletons, import, parse / serialize, radii and medial snapping, save.
void StudioServer::Impl::edit_routes() {
    http.Post("/api/auto-skeleton", post_handler([this](const Req&, const std::string&, Res& res) {
                  const Domain& d = require_domain("the curve skeleton");
                  const std::lock_guard<std::mutex> lock(auto_mutex);
                  if (!auto_body) {
                      Skeletonization sk;
                      try {
                          sk = skeletonize_surface(d.surface);
                      } catch (const Error& e) {
                          throw library_error(e);
                      }
                      auto_body = json{{"skeleton", skeleton_json(sk.skeleton)},
                                       {"obj", skeleton_text(sk.skeleton, "obj", "skeleton")}}
                                      .dump(-1, ' ', false, kUtf8Replace);
                  }
                  send_json(res, *auto_body);
              }));

    http.Post("/api/import", post_handler([](const Req& req, const std::string& body, Res& res) {
                  const std::string format = format_param(req, "ma");
                  if (format != "ma")
                      throw HttpError(400, "BadRequest", "import reads format=ma only, not '" + format + "'");
                  Skeleton medial;
                  try {
                      medial = read_medial_mesh_text(body, "request body");
                  } catch (const Error& e) {
                      throw HttpError(400, code_name(e.code()), e.what(), e.where());
                  }
                  MedialImport imp;
                  try {
                      imp = import_medial_mesh(medial);
                  } catch (const Error& e) {
                      throw library_error(e);
                  }
                  send_json(res, json{{"skeleton", skeleton_json(imp.skeleton)},
                                      {"obj", skeleton_text(imp.skeleton, "obj", "skeleton")}}
                                     .dump(-1, ' ', false, kUtf8Replace));
              }));

    http.Post("/api/parse", post_handler([](const Req& req, const std::string& body, Res& res) {
                  send_json(res, json{{"skeleton", skeleton_json(body_skeleton(req, body))}}.dump(-1, ' ', false,
                                                                                                  kUtf8Replace));
              }));

    http.Post("/api/serialize", post_handler([](const Req& req, const std::string& body, Res& res) {
                  const std::string format = format_param(req);
                  if (format != "obj" && format != "ig")
                      throw HttpError(400, "BadRequest", "serialize writes format=obj or ig, not '" + format + "'");
                  const Skeleton s = skeleton_from_json(body_json(body));
                  std::string text;
                  try {
                      text = skeleton_text(s, format, "skeleton");
                  } catch (const Error& e) {
                      throw HttpError(400, code_name(e.code()), e.what(), e.where());
                  }
                  res.set_content(text, "text/plain; charset=utf-8");
              }));

    http.Post("/api/radius-from-domain", post_handler([this](const Req& req, const std::string& body, Res& res) {
                  const Domain& d = require_domain("radius from the domain");
                  const Skeleton s = body_skeleton(req, body);
                  RadiusFromSurface rs;
                  try {
                      rs = radius_from_surface(s, *d.query);
                  } catch (const Error& e) {
                      throw library_error(e);
                  }
                  send_json(res, json{{"radii", rs.radii}, {"outside_vertices", rs.outside_vertices}}.dump(
                                     -1, ' ', false, kUtf8Replace));
              }));

    http.Post("/api/snap-medial", post_handler([this](const Req&, const std::string& body, Res& res) {
                  const Domain& d = require_domain("snapping to the medial position");
                  const json request = body_json(body);
                  if (!request.is_object() || !request.contains("points") || !request["points"].is_array())
                      throw HttpError(400, "BadRequest", "expected {\"points\": [[x, y, z], ...]}");
                  json wrapped = {{"points", request["points"]}};
                  const Skeleton pts = skeleton_from_json(wrapped);
                  json out = json::array();
                  const double eps = 1e-9 * d.query->bbox_diagonal();
                  for (const Vec3& p : pts.points) {
                      // The closest surface point c, and the surface point h hit by the ray from c through p (from
                      // inside) or from c away from p (from outside): the medial position is their midpoint (exact in a
                      // tube).
                      const ClosestPoint c = d.query->closest(p);
                      Vec3 m = p;
                      const Vec3 dir = d.query->inside(p) ? p - c.point : c.point - p;
                      if (norm(dir) > eps) {
                          const std::optional<RayHit> h = d.query->first_hit(c.point, dir, eps);
                          if (h) m = 0.5 * (c.point + h->point);
                      }
                      out.push_back({m.x, m.y, m.z});
                  }
                  send_json(res, json{{"points", out}}.dump(-1, ' ', false, kUtf8Replace));
              }));

    http.Post("/api/save", post_handler([this](const Req& req, const std::string& body, Res& res) {
                  if (session.save_target.empty())
                      throw HttpError(403, "Forbidden", "no save target: start the studio with --save PATH");
                  const Skeleton s = body_skeleton(req, body);
                  const std::lock_guard<std::mutex> lock(save_mutex);
                  try {
                      write_skeleton(session.save_target, s);
                  } catch (const Error& e) {
                      throw HttpError(e.code() == ErrorCode::IoError ? 500 : 422, code_name(e.code()), e.what(),
                                      e.where());
                  }
                  send_json(res, json{{"saved", session.save_target},
                                      {"vertices", s.points.size()},
                                      {"edges", s.edges.size()},
                                      {"faces", s.faces.size()}}
                                     .dump(-1, ' ', false, kUtf8Replace));
              }));
}

// GET of anything else: a lookup in the in-memory table, never the file system.
void StudioServer::Impl::static_routes() {
    http.Get(".*", guarded([this](const httplib::Request& req, httplib::Response& res) {
                 const auto it = files.by_url.find(req.path);
                 if (it == files.by_url.end()) throw HttpError(404, "NotFound", "no such resource: GET " + req.path);
                 res.set_header("Cache-Control", "no-cache");
                 res.set_content(it->second.body, it->second.content_type);
             }));
}

StudioServer::StudioServer(StudioSession session, StaticFiles files, StudioOptions options)
    : impl_(std::make_unique<Impl>(std::move(session), std::move(files), std::move(options))) {}

StudioServer::~StudioServer() { stop(); }

int StudioServer::bind() {
    if (impl_->port >= 0) return impl_->port;
    const std::string& host = impl_->options.host;
    const int port = impl_->options.port;
    if (port < 0 || port > 65535)
        throw Error(ErrorCode::InvalidInput, "port " + std::to_string(port) + " out of range");
    int bound = -1;
    if (port == 0) {
        bound = impl_->http.bind_to_any_port(host);
    } else if (impl_->http.bind_to_port(host, port)) {
        bound = port;
    }
    if (bound <= 0)
        throw Error(ErrorCode::IoError,
                    "cannot listen on " + host + ":" + std::to_string(port) + " (address in use or not available)");
    impl_->port = bound;
    return bound;
}

bool StudioServer::listen() {
    bind();
    return impl_->http.listen_after_bind();
}

int StudioServer::start() {
    const int port = bind();
    impl_->thread = std::thread([this] { impl_->http.listen_after_bind(); });
    while (!impl_->http.is_running() && !impl_->stopping.load())
        std::this_thread::sleep_for(std::chrono::milliseconds(1));
    return port;
}

void StudioServer::stop() {
    if (!impl_) return;
    impl_->stopping = true;
    impl_->http.stop();
    if (impl_->thread.joinable()) impl_->thread.join();
}

}  // namespace mesohex::studio
