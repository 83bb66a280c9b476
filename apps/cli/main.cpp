// mesohex: meso-skeleton guided hexahedral meshing. Arguments -> options structs; errors -> exit codes.
#include <iostream>

#include "commands.h"
#include "mesohex/core/error.h"

int main(int argc, char** argv) {
    CLI::App app{
        "mesohex: all-hex meshes guided by meso-skeletons (curve branches + quad leaflets).\n"
        "Example: mesohex quality out.mesh --json"};
    app.require_subcommand(1);
    // A flag takes no value but its own (`--best-effort=7` is an error, not true); subcommands inherit this.
    app.option_defaults()->disable_flag_override();
    int status = 0;
    mesohex::cli::register_mesh(app, &status);
    mesohex::cli::register_analyze(app, &status);
    mesohex::cli::register_quality(app, &status);
    mesohex::cli::register_convert(app, &status);
    mesohex::cli::register_generate(app, &status);
    mesohex::cli::register_import(app, &status);
    mesohex::cli::register_skeletonize(app, &status);
    mesohex::cli::register_thicken(app, &status);
    mesohex::cli::register_auto(app, &status);
    mesohex::cli::register_studio(app, &status);
    mesohex::cli::register_medial(app, &status);
    try {
        app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
        return app.exit(e);
    } catch (const mesohex::Error& e) {
        std::cerr << "mesohex: error: " << e.what() << "\n";
        return mesohex::exit_code(e.code());
    } catch (const std::exception& e) {
        // Not caught at a stage boundary (cmd_*.cpp use at_stage): still a documented code, never a bare message.
        const mesohex::Error err = mesohex::foreign_error(e, "mesohex");
        std::cerr << "mesohex: error: " << err.what() << "\n";
        return mesohex::exit_code(err.code());
    } catch (...) {
        std::cerr << "mesohex: error: internal failure: unknown exception\n";
        return 1;
    }
    return status;
}
