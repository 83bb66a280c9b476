#pragma once
// The studio's static files: a FIXED list loaded from the web directory into memory at start-up. GET requests are
// answered by looking the request path up in this table; no request path ever reaches the file system.
#include <map>
#include <string>
#include <vector>

namespace mesohex::studio {

struct StaticFile {
    std::string content_type;
    std::string body;
};

struct StaticFiles {
    std::map<std::string, StaticFile> by_url;  // "/", "/studio.css", "/app/NAME.js", "/vendor/NAME.js", ...
    std::vector<std::string> missing;          // required files not found (relative to the web directory)
};

// Loads, from `web_dir`: index.html (served as "/" and "/index.html"), studio.css, every NAME.js directly in
// `web_dir` (served as "/app/NAME.js"; NAME made of letters, digits, '_' and '-'), and from node_modules/three:
// build/three.module.js, examples/jsm/controls/{OrbitControls,TransformControls}.js (required) and a few optional
// example modules (see the table in static_files.cpp), served as "/vendor/<file name>". Missing required files are
// listed in `missing` (the API still works without the page). A file that exists but cannot be read is an
// Error(IoError).
StaticFiles load_static_files(const std::string& web_dir);

// Content type for a file name by its extension (html, css, js, json, png, svg; else application/octet-stream).
std::string content_type_for(const std::string& file_name);

}  // namespace mesohex::studio
