#pragma once
// Helpers for the studio server tests: a server started in-process on a free loopback port, and an HTTP client.
#include <gtest/gtest.h>

#include <memory>
#include <string>

#include <httplib.h>
#include <nlohmann/json.hpp>

#include "server.h"

namespace mesohex::test {

struct RunningStudio {
    std::unique_ptr<studio::StudioServer> server;
    int port = 0;
    std::unique_ptr<httplib::Client> client;
};

inline RunningStudio start_studio(studio::StudioSession session, studio::StaticFiles files = {},
                                  studio::StudioOptions options = {}) {
    options.host = "127.0.0.1";
    options.port = 0;
    RunningStudio s;
    s.server = std::make_unique<studio::StudioServer>(std::move(session), std::move(files), options);
    s.port = s.server->start();
    s.client = std::make_unique<httplib::Client>("127.0.0.1", s.port);
    s.client->set_read_timeout(120, 0);
    return s;
}

// The body as JSON (an empty object when it is not JSON, so that the expectations fail with the text shown).
inline nlohmann::json body_json(const httplib::Result& r) {
    if (!r) return nlohmann::json::object();
    return nlohmann::json::parse(r->body, nullptr, false).is_discarded() ? nlohmann::json::object()
                                                                         : nlohmann::json::parse(r->body);
}

}  // namespace mesohex::test
