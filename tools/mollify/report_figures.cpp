// Report section 5: what a person would rather look at than read: kernel
// shapes and their potentials (evaluated by the runtime), the vortex sheet
// (the vortex-sheet scene); the convergence plots are in section 4.
#include "report.hpp"

#include <mollify/error.hpp>
#include <mollify/exact.hpp>
#include <mollify/kernel.hpp>

#include <algorithm>

namespace fs = std::filesystem;

namespace mollify::app {

namespace {

// One per family, and the high orders whose shapes go negative.
constexpr const char* shown[] = {"wendland:k=2", "wendland:k=4,l=4", "wendland-missing:k=2", "mollifier:M=4",
                                 "mollifier:M=4,order=6", "combo:m=3,base=wendland:k=2", "cubic-spline"};

void shapes(Output& out, SectionResult& r) {
    constexpr int samples = 301;
    Table t{{"kernel", "q", "W", "dW/dq", "phi"}, {}};
    std::string blocks;  // gnuplot: one block per kernel, "q W/W(0) phi"
    for (const char* spec : shown) {
        const Kernel k = mollify::exact::kernel(spec, 3);
        const double w0 = k.value(0.0, 1.0);
        for (int i = 0; i < samples; ++i) {
            const double q = 1.5 * i / (samples - 1);
            const std::string w = format(k.value(q, 1.0), 10);
            const std::string phi = k.has_potential() ? format(k.potential(q, 1.0), 10) : "nan";
            t.add({spec, format(q, 6), w, format(k(QuantityId::dr, q, 1.0), 10), phi});
            blocks += format(q, 6) + " " + format(k.value(q, 1.0) / w0, 10) + " " + phi + "\n";
        }
        blocks += "\n\n";
    }
    out.csv("shapes.csv", t);
    out.write("shapes.dat", blocks);
    auto plot = [&](const std::string& column, const std::string& label) {
        std::string s = "set datafile separator whitespace; set xlabel 'r/h'; set ylabel '" + label +
                        "'; set key outside right; set grid; set title '" + label + ", D = 3, h = 1'\nplot ";
        for (std::size_t i = 0; i < std::size(shown); ++i)
            s += std::string(i ? ", " : "") + "'shapes.dat' index " + std::to_string(i) + " using 1:" + column +
                 " with lines lw 2 title '" + shown[i] + "'";
        return s + "\n";
    };
    out.plot("kernels.png", plot("2", "W(r) / W(0)"), 1100, 600);
    out.plot("potentials.png", plot("3", "potential φ(r), Δφ = W"), 1100, 600);
    r.markdown += "Kernel shapes (scaled by W(0); the high orders go negative) and their Poisson potentials in 3D (from the runtime; the potential equals the "
                  "Green's function −1/(4πr) beyond the support; the cubic spline has no potential in the tables):\n\n"
                  "![kernels](figures/kernels.png)\n\n![potentials](figures/potentials.png)\n\n";
}

void vortex_sheet(const ReportContext& ctx, Output& out, SectionResult& r) {
    const Scene scene = report_scene(ctx, "report/vortex_sheet.toml");
    run_scene_in(scene, out, "vortex-sheet");
    std::vector<std::string> pngs;
    for (const auto& e : fs::directory_iterator(out.staging() / "vortex-sheet"))
        if (e.path().extension() == ".png") pngs.push_back(e.path().filename().string());
    std::sort(pngs.begin(), pngs.end());
    r.markdown += "The periodic vortex sheet (" + scene.title() + "; [figures/vortex-sheet/](figures/vortex-sheet/summary.md)):\n\n";
    for (const std::string& p : pngs) r.markdown += "![" + p + "](figures/vortex-sheet/" + p + ")\n\n";
}

}  // namespace

void report_figures(const ReportContext& ctx, Output& out, SectionResult& r) {
    shapes(out, r);
    r.markdown += "Convergence of Franz's SPH: [section 4](#studies) (Q_kin against ε).\n\n";
    try {
        vortex_sheet(ctx, out, r);
    } catch (const Error& e) {
        r.failures.push_back(std::string("vortex sheet: ") + e.what());
    }
}

}  // namespace mollify::app
