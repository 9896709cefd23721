// Report section 3: speed against error. Kernel throughput beside the error it
// achieves (kernel_bench, same run), SPH CPU time against Q_kin (the Franz
// torus study of section 4), Poisson solvers' time against error (the
// poisson-free scene).
#include "process.hpp"
#include "report.hpp"

#include <mollify/error.hpp>

#include <fstream>
#include <sstream>

namespace fs = std::filesystem;

namespace mollify::app {

namespace {

// Everything after the first line (the experiment's own title).
std::string body(const std::string& summary) {
    const std::size_t nl = summary.find('\n');
    return nl == std::string::npos ? std::string() : summary.substr(nl + 1);
}

// kernel_bench's own level-2 headings (its ratio tables) nested below this
// section's level-3 heading: as level-4 ones.
std::string nested(std::string md) {
    for (std::size_t at = md.find("\n## "); at != std::string::npos; at = md.find("\n## ", at + 6))
        md.replace(at, 4, "\n#### ");
    return md;
}

void kernels(const ReportContext& ctx, Output& out, SectionResult& r) {
    // Batches of 10^6 points, a short minimum time per case (the full run
    // is `cmake --build build --target bench-kernels`).
    const ProcessResult p = run_process((ctx.tools / "kernel_bench").string(),
                                        {"--benchmark_filter=/1000000$", "--benchmark_min_time=0.05",
                                         "--md=" + (out.staging() / "kernel_bench.md").string()},
                                        {}, "cmake --build build --target kernel_bench");
    if (!p.ok()) fail("kernel_bench failed (exit status " + std::to_string(p.exit_status) + "): " + p.err);
    const std::string md = read_text(out.staging() / "kernel_bench.md");
    const std::size_t table = md.find("| benchmark");
    if (table == std::string::npos) fail("kernel_bench wrote no table");
    r.markdown += "### Kernel evaluation: throughput beside accuracy\n\n"
                  "Google Benchmark, batches of 10^6 random radii, 3D; mollify's compile-time (`static`) and run-time "
                  "(`runtime`) forms against the expanded-monomial and `pow` forms; `ulp_W`, `ulp_G`: the largest "
                  "error of W and W′/r each form achieves (same build, measured in the same run); `bound`: the "
                  "FMA-pipe lower bound of mollify's form in cycles.\n\n" +
                  nested(md.substr(table)) + "\n";
}

}  // namespace

void report_speed(const ReportContext& ctx, Output& out, SectionResult& r) {
    try {
        kernels(ctx, out, r);
    } catch (const Error& e) {
        r.failures.push_back(std::string("kernel throughput: ") + e.what());
    }

    r.markdown += "### SPH: CPU time against error\n\n";
    const fs::path franz = out.staging().parent_path() / "studies" / "franz-torus" / "summary.md";
    if (fs::exists(franz)) {
        r.markdown += "Franz's torus case (section 4), the process's CPU time of each run against its Q_kin at t = 0.8:"
                      "\n\n![CPU time against Q_kin](studies/franz-torus/time_vs_error.png)\n\n" +
                      markdown_section(read_text(franz), "## Cost of an error level");
    } else {
        r.markdown += "The Franz torus study (section 4) did not run; no SPH timings.\n\n";
        r.failures.push_back("SPH time against error: the Franz torus study did not run");
    }

    r.markdown += "### Poisson solvers: time against error\n\n";
    try {
        const Scene scene = report_scene(ctx, "poisson_free.toml");
        r.markdown += body(run_scene_in(scene, out, "poisson-free"));
        r.markdown += "\n(Folder: [speed/poisson-free/](speed/poisson-free/summary.md).)\n\n";
    } catch (const Error& e) {
        r.failures.push_back(std::string("Poisson solvers: ") + e.what());
    }
}

}  // namespace mollify::app
