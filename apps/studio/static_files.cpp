#include "static_files.h"

#include <algorithm>
#include <filesystem>
#include <system_error>

#include "mesohex_io/text_input.h"

namespace mesohex::studio {

namespace {

struct Entry {
    const char* url;
    const char* file;  // relative to the web directory
    bool required;
};

// The fixed table. The app's own modules (/app/NAME.js) are added from the web directory's top-level *.js files.
constexpr Entry kFiles[] = {
    {"/", "index.html", true},
    {"/index.html", "index.html", true},
    {"/studio.css", "studio.css", true},
    {"/vendor/three.module.js", "node_modules/three/build/three.module.js", true},
    {"/vendor/OrbitControls.js", "node_modules/three/examples/jsm/controls/OrbitControls.js", true},
    {"/vendor/TransformControls.js", "node_modules/three/examples/jsm/controls/TransformControls.js", true},
    {"/vendor/BufferGeometryUtils.js", "node_modules/three/examples/jsm/utils/BufferGeometryUtils.js", false},
    {"/vendor/SelectionBox.js", "node_modules/three/examples/jsm/interactive/SelectionBox.js", false},
    {"/vendor/SelectionHelper.js", "node_modules/three/examples/jsm/interactive/SelectionHelper.js", false},
};

bool is_module_name(const std::string& name) {
    if (name.size() <= 3 || name.substr(name.size() - 3) != ".js") return false;
    return std::all_of(name.begin(), name.end() - 3, [](char c) {
        return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '_' || c == '-';
    });
}

}  // namespace

std::string content_type_for(const std::string& file_name) {
    const std::string ext = lower_extension(file_name);
    if (ext == "html") return "text/html; charset=utf-8";
    if (ext == "css") return "text/css; charset=utf-8";
    if (ext == "js" || ext == "mjs") return "text/javascript; charset=utf-8";
    if (ext == "json") return "application/json";
    if (ext == "png") return "image/png";
    if (ext == "svg") return "image/svg+xml";
    return "application/octet-stream";
}

StaticFiles load_static_files(const std::string& web_dir) {
    namespace fs = std::filesystem;
    StaticFiles out;
    const fs::path root(web_dir);
    for (const Entry& e : kFiles) {
        const fs::path p = root / e.file;
        std::error_code ec;
        if (!fs::is_regular_file(p, ec)) {
            if (e.required && std::find(out.missing.begin(), out.missing.end(), e.file) == out.missing.end())
                out.missing.push_back(e.file);
            continue;
        }
        out.by_url[e.url] = {content_type_for(e.file), read_whole_file(p.string())};
    }
    std::error_code ec;
    std::vector<std::string> modules;
    for (fs::directory_iterator it(root, ec), end; !ec && it != end; it.increment(ec)) {
        const std::string name = it->path().filename().string();
        std::error_code ec2;
        if (is_module_name(name) && fs::is_regular_file(it->path(), ec2)) modules.push_back(name);
    }
    std::sort(modules.begin(), modules.end());
    for (const std::string& name : modules)
        out.by_url["/app/" + name] = {content_type_for(name), read_whole_file((root / name).string())};
    return out;
}

}  // namespace mesohex::studio
