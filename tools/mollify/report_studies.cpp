// Report section 4: Franz's convergence study on R and on T beside the
// thesis' Tables 6.2 and 6.4, and Belley's estimation study beside the
// paper's tables, on the reduced grids of scenes/report/ (the full studies:
// scenes/franz_line.toml, franz_torus.toml, belley.toml).
#include "report.hpp"

#include <mollify/error.hpp>

namespace mollify::app {

namespace {

struct Study {
    const char* scene;   // in scenes/report/
    const char* folder;  // in the report's studies/
    const char* heading;
    const char* excerpt;  // the part of its summary shown in the index
};

constexpr Study studies[] = {
    {"report/franz_line.toml", "franz-line", "Franz §6.2.1 on R (Table 6.2)", "## Rates"},
    {"report/franz_torus.toml", "franz-torus", "Franz §6.2.2 on the torus (Table 6.4)", "## Rates"},
    {"belley.toml", "belley", "Belley §5 (Tables 1–25)", "## Agreement with the printed tables"},
};

}  // namespace

void report_studies(const ReportContext& ctx, Output& out, SectionResult& r) {
    for (const Study& s : studies) {
        r.markdown += std::string("### ") + s.heading + "\n\n";
        try {
            const Scene scene = report_scene(ctx, s.scene);
            const std::string summary = run_scene_in(scene, out, s.folder);
            const std::size_t first = summary.find("\n\n"), second = summary.find("\n\n", first + 2);
            if (first != std::string::npos && second != std::string::npos)
                r.markdown += summary.substr(first + 2, second - first) + "\n";  // the run's description
            r.markdown += markdown_section(summary, s.excerpt);
            r.markdown += std::string("\nEverything (data, plots, the rest of the summary): [studies/") + s.folder +
                          "/](studies/" + s.folder + "/summary.md).\n\n";
        } catch (const Error& e) {
            r.failures.push_back(std::string(s.heading) + ": " + e.what());
        }
    }
    r.markdown += "![Franz torus: Q_kin against ε](studies/franz-torus/q_kin.png)\n\n";
}

}  // namespace mollify::app
