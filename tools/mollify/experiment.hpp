// The experiments a scene can name (scene.experiment). Each reads its own
// section of the scene, runs, and writes CSV data, PNG plots and a Markdown
// summary into the Output; it throws mollify::Error on bad parameters
// (before writing anything when it can tell in advance).
#pragma once

#include "output.hpp"
#include "scene.hpp"

#include <mollify/error.hpp>
#include <mollify/precision.hpp>

#include <span>
#include <string>
#include <string_view>

namespace mollify::app {

struct Experiment {
    std::string_view name;     // scene.experiment
    std::string_view summary;  // one line for `mollify run --help` / errors
    void (*run)(const Scene&, Output&);
};

// f(), whose Error (a library's check of a value the scene gave) is
// rethrown naming the scene's file, line and key.
template <class F>
decltype(auto) checked(const Scene& scene, std::string_view key, F&& f) {
    try {
        return f();
    } catch (const Error& e) {
        scene.reject(key, e.what());
    }
}

// The Precision a scene names under `key` ("accurate", the default, or
// "fast"); an unknown name is an Error naming the file, line and key.
inline Precision scene_precision(const Scene& scene, std::string_view key) {
    return checked(scene, key, [&] { return precision(scene.string(key, "accurate")); });
}

// The most time steps a scene may ask for: far beyond any scene's hours of
// work (the vortex sheet's scenes take 400 steps), so an
// absurd time, dt or amplitude is refused naming it instead of running for
// ever (or, for the vortex sheet, overflowing a step count).
inline constexpr double max_time_steps = 1e7;

// Refuses `key` when reaching its time takes more than max_time_steps steps.
inline void check_step_count(const Scene& scene, std::string_view key, double steps, const std::string& why) {
    if (!(steps <= max_time_steps))
        scene.reject(key, why + " takes " + format(steps, 3) + " steps, more than the 10^7 a scene may run");
}

// All experiments, in the order `mollify` lists them.
std::span<const Experiment> experiments();

// The experiment scene.experiment names; an Error naming the file, the key,
// the line and the known experiments if there is none of that name.
const Experiment& find_experiment(const Scene& scene);

// Defined one per file: franz.cpp, belley.cpp, sph_periodic.cpp,
// poisson_free.cpp, poisson_periodic.cpp, vortex_sheet.cpp, kernel_values.cpp, all compiled into
// the mollify command (franz and belley only with MOLLIFY_STUDIES=ON; else
// studies_left_out.cpp). Tests that link mollify_app without the experiments
// link test doubles of them instead (tests/experiment_doubles.cpp).
void run_franz(const Scene&, Output&);
void run_belley(const Scene&, Output&);
void run_sph_periodic(const Scene&, Output&);
void run_poisson_free(const Scene&, Output&);
void run_poisson_periodic(const Scene&, Output&);
void run_vortex_sheet(const Scene&, Output&);
void run_kernel_values(const Scene&, Output&);

}  // namespace mollify::app
