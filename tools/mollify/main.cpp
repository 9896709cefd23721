// mollify: runs scenes (README, "Scenes and the mollify command").
//   mollify run SCENE.toml [--out DIR]   run a scene, write its output folder atomically
//   mollify list [DIR]                   the experiments, and the scenes in DIR (default scenes/)
//   mollify report [--out DIR]           the verification report (report.hpp)
//   mollify verify SPEC --dim D ...      someone's kernel against the exact one (verify_command.hpp;
//                                        its own exit status: 0 within the bound, 1 outside, 2 bad input)
// Exit status: 0 success, 1 a mollify::Error (bad scene, failed run; message on
// stderr as "mollify: error: ..."), 2 command-line misuse.
#include "data_dir.hpp"
#include "experiment.hpp"
#include "output.hpp"
#include "report.hpp"
#include "scene.hpp"
#include "verify_command.hpp"

#include <mollify/error.hpp>

#include <CLI/CLI.hpp>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <iomanip>
#include <iostream>

#include <unistd.h>

using namespace mollify::app;
namespace fs = std::filesystem;

namespace {

constexpr int run_failed = 1;
constexpr int bad_usage = 2;

int run_scene(const std::string& file, const std::string& out_option) {
    const Scene scene = Scene::load(file);
    const Experiment& experiment = find_experiment(scene);
    const fs::path destination = out_option.empty() ? fs::path("out") / scene.name() : fs::path(out_option);
    Output out(destination);
    out.write("scene.toml", scene.text());
    experiment.run(scene, out);
    out.commit();
    progress_clear();
    std::size_t files = 0;
    for (const auto& e : fs::recursive_directory_iterator(out.destination())) files += e.is_regular_file();
    std::cout << "mollify: " << scene.name() << " (" << experiment.name << "): wrote " << files << " files to "
              << out.destination().string() << "/ (summary: " << (out.destination() / "summary.md").string() << ")\n";
    return 0;
}

// scenes/ in the working directory, else the installed or the source tree's.
fs::path default_scene_dir() {
    std::error_code ec;
    if (fs::is_directory("scenes", ec)) return "scenes";
    return mollify::data_dir("scenes", MOLLIFY_SCENES_DIR);
}

int run_list(const std::string& dir_option) {
    std::cout << "experiments:\n";
    std::size_t width = 0;  // the longest name and two spaces: "poisson-periodic" ran into its summary
    for (const Experiment& e : experiments()) width = std::max(width, e.name.size() + 2);
    for (const Experiment& e : experiments())
        std::cout << "  " << std::left << std::setw(static_cast<int>(width)) << e.name << e.summary << "\n";
    const fs::path dir = dir_option.empty() ? default_scene_dir() : fs::path(dir_option);
    std::error_code ec;
    if (!fs::is_directory(dir, ec)) mollify::fail("scene folder " + dir.string() + " does not exist");
    std::vector<fs::path> files;
    for (const auto& e : fs::directory_iterator(dir))
        if (e.is_regular_file() && e.path().extension() == ".toml") files.push_back(e.path());
    std::sort(files.begin(), files.end());
    std::cout << "scenes in " << dir.string() << "/:" << (files.empty() ? " none\n" : "\n");
    for (const fs::path& f : files) {
        try {
            const Scene s = Scene::load(f);
            std::cout << "  " << f.string() << "  [" << s.experiment() << "]  " << s.title() << "\n";
        } catch (const mollify::Error& e) {
            std::cout << "  " << f.string() << "  (invalid: " << e.what() << ")\n";
        }
    }
    return 0;
}

}  // namespace

// OpenMP threads that spin while waiting (libgomp's default) burn CPU time
// that the experiments' CPU-time measurements would count, and slow other
// work on a shared machine. libgomp reads OMP_WAIT_POLICY when it is loaded,
// before main, so mollify re-executes itself once with it set to passive
// (unless the user chose a policy).
static void wait_passively(char** argv) {
    if (std::getenv("OMP_WAIT_POLICY")) return;
    ::setenv("OMP_WAIT_POLICY", "passive", 1);
    ::execv("/proc/self/exe", argv);  // returns only on failure: then run as we are
}

int main(int argc, char** argv) {
    wait_passively(argv);
    CLI::App app{"mollify: the verification report, and experiments run from scene files (scenes/*.toml)"};
    app.require_subcommand(1);

    auto* run = app.add_subcommand("run", "run a scene; writes CSV, PNG plots and summary.md into its output folder");
    std::string scene_file, out;
    run->add_option("scene", scene_file, "scene file, e.g. scenes/franz-torus.toml")->required();
    run->add_option("--out", out, "output folder (default: out/<scene.name>)");

    auto* list = app.add_subcommand("list", "list the experiments and the scenes with their titles");
    std::string scene_dir;
    list->add_option("dir", scene_dir, "scene folder (default: scenes/ here, else the source tree's)");

    std::string names;
    for (const Experiment& e : experiments()) names += "\n  " + std::string(e.name) + "  " + std::string(e.summary);
    run->footer("Experiments (scene.experiment):" + names);

    auto* report = app.add_subcommand(
        "report", "the verification report: report/index.md with figures (exactness, accuracy, speed against error, "
                  "reproduced studies); exit status 0 only if every section passed");
    ReportOptions report_options;
    report->add_option("--out", report_options.out, "report folder (written atomically)")->capture_default_str();
    report->add_option("--scenes", report_options.scenes,
                       "a scenes/ folder to read the report's scenes from (default: the copies compiled in)");
    report->add_option("--only", report_options.only,
                       "sections to run: exactness, accuracy, speed, studies, figures (default: all)");

    VerifyOptions verify_options;
    auto* verify = add_verify_command(app, verify_options);

    try {
        app.parse(argc, argv);
    } catch (const CLI::CallForHelp& e) {
        return app.exit(e);
    } catch (const CLI::CallForAllHelp& e) {
        return app.exit(e);
    } catch (const CLI::ParseError& e) {
        std::cerr << "mollify: " << e.what() << "\n" << "run 'mollify --help' for usage\n";
        return bad_usage;
    }
    if (*verify) return run_verify(verify_options);
    try {
        if (*run) return run_scene(scene_file, out);
        if (*list) return run_list(scene_dir);
        if (*report) return run_report(report_options);
    } catch (const std::exception& e) {  // mollify::Error, and filesystem errors
        progress_clear();
        std::cerr << "mollify: error: " << e.what() << "\n";
        return run_failed;
    }
    return 0;
}
