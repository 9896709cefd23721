#include "report.hpp"

#include "data_dir.hpp"
#include "experiment.hpp"

#include <mollify/error.hpp>

#include <algorithm>
#include <array>
#include <chrono>
#include <ctime>
#include <fstream>
#include <iostream>
#include <sstream>
#include <thread>
#include <utility>

#include <unistd.h>

namespace fs = std::filesystem;

namespace mollify::app {

namespace {

// scenes/*.toml and scenes/report/*.toml, named relative to scenes/
// ("belley.toml", "report/franz_line.toml"), compiled in by
// tools/mollify/embed_scenes.cmake.
constexpr std::pair<std::string_view, std::string_view> embedded_scenes[] = {
#include "report_scenes.inc"
};

constexpr std::array<Section, 5> sections = {{
    {"exactness", "1. Exactness: the catalogue, its certificates, the errata", report_exactness},
    {"accuracy", "2. Accuracy of the double-precision runtime", report_accuracy},
    {"speed", "3. Speed against error", report_speed, "studies"},
    {"studies", "4. Reproduced studies", report_studies},
    {"figures", "5. Figures", report_figures},
}};

// The folder of this executable (mollify-gen and the other tools are built beside it).
fs::path own_folder() {
    std::error_code ec;
    const fs::path self = fs::read_symlink("/proc/self/exe", ec);
    return ec ? fs::current_path() : self.parent_path();
}

std::string machine() {
    std::ifstream cpu("/proc/cpuinfo");
    std::string line, model = "unknown CPU";
    while (std::getline(cpu, line))
        if (line.rfind("model name", 0) == 0) {
            model = line.substr(line.find(':') + 2);
            break;
        }
    return model + ", " + std::to_string(std::thread::hardware_concurrency()) + " hardware threads";
}

std::string now() {
    const std::time_t t = std::time(nullptr);
    char buf[64];
    std::strftime(buf, sizeof buf, "%Y-%m-%d %H:%M:%S %Z", std::localtime(&t));
    return buf;
}

struct Ran {
    const Section* section;
    SectionResult result;
    double seconds = 0;
};

Ran run_section(const Section& s, const ReportContext& ctx, Output& report, std::size_t index, std::size_t count) {
    progress("report", index, count, std::string(s.id));
    Ran ran{&s, {}, 0};
    const auto start = std::chrono::steady_clock::now();
    try {
        Output folder(report.staging() / std::string(s.id));
        s.run(ctx, folder, ran.result);
        folder.summary() = "# " + std::string(s.title) + "\n\n" + ran.result.markdown;
        folder.commit();
    } catch (const std::exception& e) {  // this section fails; the report goes on
        ran.result.failures.push_back(std::string("the section stopped: ") + e.what());
    }
    ran.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    progress_clear();
    std::cerr << "mollify report: " << s.id << (ran.result.failures.empty() ? " passed" : " FAILED") << " ("
              << format(ran.seconds, 3) << " s)\n";
    for (const std::string& f : ran.result.failures) std::cerr << "  " << f << "\n";
    return ran;
}

std::string index_markdown(const std::vector<Ran>& ran, double seconds) {
    std::string md = "# mollify verification report\n\n";
    md += "Made by `mollify report` on " + now() + ", on this machine (" + machine() + ") in " + format(seconds, 3) +
          " s. Every number and figure below was measured in this run.\n\n";
    Table status{{"section", "result", "time [s]", "details"}, {}};
    for (const Ran& r : ran)
        status.add({"[" + std::string(r.section->title) + "](#" + std::string(r.section->id) + ")",
                    r.result.failures.empty() ? "passed" : "**FAILED** (" + std::to_string(r.result.failures.size()) + ")",
                    format(r.seconds, 3), "[" + std::string(r.section->id) + "/](" + std::string(r.section->id) + "/summary.md)"});
    md += status.markdown() + "\n";
    for (const Ran& r : ran) {
        md += "<a id=\"" + std::string(r.section->id) + "\"></a>\n\n## " + std::string(r.section->title) + "\n\n";
        if (!r.result.failures.empty()) {
            md += "**This section failed:**\n\n";
            for (const std::string& f : r.result.failures) md += "- " + f + "\n";
            md += "\n";
        }
        md += r.result.markdown + "\n";
    }
    return md;
}

}  // namespace

Scene report_scene(const ReportContext& ctx, std::string_view name) {
    if (!ctx.scenes.empty()) return Scene::load(ctx.scenes / std::string(name));
    for (const auto& [file, text] : embedded_scenes)
        if (file == name)  // origin in the source tree: relative paths in the scene (printed tables) resolve there
            return Scene::parse(text, (fs::path(mollify::data_dir("scenes", MOLLIFY_SCENES_DIR)) / std::string(name)).string());
    fail("scene " + std::string(name) + " is not compiled in (scenes/)");
}

std::string run_scene_in(const Scene& scene, Output& out, const std::string& sub) {
    const Experiment& experiment = find_experiment(scene);
    Output folder(out.staging() / sub);
    folder.write("scene.toml", scene.text());
    experiment.run(scene, folder);
    const std::string summary = folder.summary();
    folder.commit();
    return summary;
}

std::string read_text(const fs::path& file) {
    std::ifstream in(file, std::ios::binary);
    std::ostringstream s;
    s << in.rdbuf();
    return s.str();
}

std::string markdown_section(const std::string& markdown, std::string_view heading) {
    const std::size_t level = heading.find_first_not_of('#');
    std::istringstream in(markdown);
    std::string line, part;
    bool inside = false;
    while (std::getline(in, line)) {
        if (inside) {
            const std::size_t l = line.find_first_not_of('#');
            if (l != std::string::npos && l > 0 && l <= level && line.size() > l && line[l] == ' ') break;
            part += line + "\n";
        } else if (line.rfind(heading, 0) == 0) {
            inside = true;
        }
    }
    return part;
}

int run_report(const ReportOptions& options) {
    std::vector<const Section*> chosen;
    for (const std::string& id : options.only) {
        const Section* found = nullptr;
        for (const Section& s : sections)
            if (s.id == id) found = &s;
        if (!found) {
            std::string known;
            for (const Section& s : sections) known += (known.empty() ? "" : ", ") + std::string(s.id);
            fail("unknown report section '" + id + "' (known: " + known + ")");
        }
        chosen.push_back(found);
    }
    if (chosen.empty())
        for (const Section& s : sections) chosen.push_back(&s);

    const ReportContext ctx{own_folder(), fs::path(mollify::data_dir("generated", MOLLIFY_GENERATED_DIR)), options.scenes};
    const auto start = std::chrono::steady_clock::now();
    Output report(options.out);
    // Run order: a section after the one it reads; the index keeps the order of `sections`.
    std::vector<const Section*> order = chosen;
    std::stable_partition(order.begin(), order.end(), [&](const Section* s) {
        return s->reads.empty() || std::none_of(chosen.begin(), chosen.end(), [&](const Section* o) { return o->id == s->reads; });
    });
    std::vector<Ran> ran;
    for (std::size_t i = 0; i < order.size(); ++i) ran.push_back(run_section(*order[i], ctx, report, i, order.size()));
    std::sort(ran.begin(), ran.end(), [](const Ran& a, const Ran& b) { return a.section < b.section; });
    progress("report", chosen.size(), chosen.size(), "index.md");
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    report.write("index.md", index_markdown(ran, seconds));
    report.summary() = "See index.md.\n";
    report.commit();
    progress_clear();
    std::size_t failed = 0;
    for (const Ran& r : ran) failed += !r.result.failures.empty();
    std::cout << "mollify report: " << ran.size() - failed << " of " << ran.size() << " sections passed; wrote "
              << (report.destination() / "index.md").string() << " (" << format(seconds, 3) << " s)\n";
    return failed == 0 ? 0 : 1;
}

}  // namespace mollify::app
