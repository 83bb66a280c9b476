// `mesohex studio [SKELETON] [--surface DOMAIN] [--medial FILE.ma] [--port N] [--host H] [--save PATH]`: the browser
// studio (docs/studio.md). Reads the files named here, then serves the page and the JSON API until Ctrl+C / SIGTERM.
// Binds 127.0.0.1 unless --host says otherwise (with a warning). Prints exactly one line on stdout once listening:
// "mesohex studio: http://HOST:PORT/".
#include <atomic>
#include <chrono>
#include <csignal>
#include <iostream>
#include <memory>
#include <string>
#include <thread>

#include <pthread.h>
#include <signal.h>

#include "commands.h"
#include "mesohex/core/error.h"
#include "mesohex/stages/medial_import.h"
#include "mesohex_io/medial_io.h"
#include "mesohex_io/skeleton_io.h"
#include "mesohex_io/surface_io.h"
#include "mesohex_io/text_input.h"
#include "server.h"

namespace mesohex::cli {

namespace {

struct StudioArgs {
    std::string skeleton;
    std::string surface;
    std::string medial;
    std::string save;
    std::string host = "127.0.0.1";
    int port = 8080;
    std::string web_dir = MESOHEX_STUDIO_WEB_DIR;
};

int run_studio(const StudioArgs& args) {
    // SIGINT / SIGTERM are blocked in every thread (blocked before any thread starts, so the library's and the
    // server's threads inherit the mask) and taken by one thread with sigwait, which stops the server.
    sigset_t stop_signals;
    sigemptyset(&stop_signals);
    sigaddset(&stop_signals, SIGINT);
    sigaddset(&stop_signals, SIGTERM);
    pthread_sigmask(SIG_BLOCK, &stop_signals, nullptr);

    if (args.host != "127.0.0.1" && args.host != "localhost")
        std::cerr << "mesohex studio: warning: listening on " << args.host
                  << ", not only on this machine (127.0.0.1): anyone who can reach it can use the studio\n";
    if (!args.save.empty()) {
        const std::string ext = lower_extension(args.save);
        if (ext != "obj" && ext != "ig")
            throw Error(ErrorCode::InvalidInput, args.save + ": --save must name a .obj or .ig file");
    }
    studio::StudioSession session;
    if (!args.skeleton.empty()) {
        session.skeleton = read_skeleton(args.skeleton);
        session.skeleton_name = args.skeleton;
    }
    if (!args.surface.empty()) {
        session.domain = read_surface(args.surface);
        session.domain_name = args.surface;
    }
    if (!args.medial.empty()) session.medial = import_medial_mesh(read_medial_mesh(args.medial)).skeleton;
    session.save_target = args.save;
    studio::StaticFiles files = studio::load_static_files(args.web_dir);
    if (!files.missing.empty()) {
        std::cerr << "mesohex studio: warning: the page is incomplete (missing in " << args.web_dir << ":";
        for (const std::string& f : files.missing) std::cerr << " " << f;
        std::cerr << "; run ./mesohex.sh deps); the API works\n";
    }
    studio::StudioOptions options;
    options.host = args.host;
    options.port = args.port;
    studio::StudioServer server(std::move(session), std::move(files), options);
    const int port = server.bind();
    const std::string shown_host = args.host.find(':') != std::string::npos ? "[" + args.host + "]" : args.host;
    std::cout << "mesohex studio: http://" << shown_host << ":" << port << "/" << std::endl;

    std::atomic<bool> done{false};
    std::thread signals([&] {
        int sig = 0;
        sigwait(&stop_signals, &sig);
        if (done.load()) return;
        std::cerr << "mesohex studio: stopping\n";
        // Until listen() has started, stop() has nothing to stop: repeat until it returns.
        while (!done.load()) {
            server.stop();
            std::this_thread::sleep_for(std::chrono::milliseconds(20));
        }
    });
    const bool ok = server.listen();
    done = true;
    pthread_kill(signals.native_handle(), SIGTERM);  // wakes the sigwait when the server stopped by itself
    signals.join();
    return ok ? 0 : 1;
}

}  // namespace

void register_studio(CLI::App& app, int* status) {
    auto args = std::make_shared<StudioArgs>();
    CLI::App* cmd = app.add_subcommand(
        "studio", "Browser studio: model a meso-skeleton over its domain and see the hex mesh live (docs/studio.md).");
    cmd->add_option("skeleton", args->skeleton, "Skeleton to open (.skel, .cg, .cgr, .ig, .obj); default: empty");
    cmd->add_option("--surface", args->surface,
                    "Domain surface (.off .obj .stl .ply): shown, and the final mesh is fit to it");
    cmd->add_option("--medial", args->medial, "Medial mesh (.ma) to import as a starting meso-skeleton");
    cmd->add_option("--port", args->port, "Port (0 = any free port)")
        ->capture_default_str()
        ->check(CLI::Range(0, 65535));
    cmd->add_option("--host", args->host,
                    "Address to listen on (anything but 127.0.0.1 opens the studio to the network)")
        ->capture_default_str();
    cmd->add_option("--save", args->save,
                    "File the page's Save writes (.obj or .ig); without it the page only downloads");
    cmd->add_option("--web-dir", args->web_dir, "Directory of the page (development)")->capture_default_str();
    cmd->footer(
        "Example: mesohex studio data/tiny/tripod.obj --save tripod_edited.obj\n"
        "Then open the printed URL in a browser. Ctrl+C stops it.");
    cmd->callback([args, status]() { *status = run_studio(*args); });
}

}  // namespace mesohex::cli
