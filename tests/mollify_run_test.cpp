// The mollify command as a user runs it (tools/mollify): a malformed scene
// exits 1 with a message naming the value and leaves no output folder;
// command-line misuse exits 2; `mollify list` lists experiments and scenes.
#include "command.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>
#include <sys/wait.h>
#include <unistd.h>

namespace fs = std::filesystem;

namespace {

using mollify::testing::Outcome;
using mollify::testing::slurp;

// A fresh working folder per test (ctest may run tests in parallel).
struct Workdir {
    fs::path dir;
    Workdir() {
        std::string t = (fs::temp_directory_path() / "mollify-run-test-XXXXXX").string();
        dir = ::mkdtemp(t.data());
    }
    ~Workdir() { fs::remove_all(dir); }
    void file(const std::string& name, const std::string& text) const {
        fs::create_directories((dir / name).parent_path());
        std::ofstream(dir / name) << text;
    }
    // Runs `mollify ARGS` in this folder.
    Outcome run(const std::string& args) const {
        return mollify::testing::run_command("cd '" + dir.string() + "' && " + MOLLIFY + " " + args, dir / ".run");
    }
    std::vector<std::string> entries() const {
        std::vector<std::string> v;
        for (const auto& e : fs::directory_iterator(dir)) v.push_back(e.path().filename().string());
        std::sort(v.begin(), v.end());
        return v;
    }
    // Each scene head + body exits 1 with its message and writes nothing.
    void expect_refused(const std::string& head, const std::vector<std::pair<std::string, std::string>>& cases) const {
        for (const auto& [body, message] : cases) {
            file("scenes/bad.toml", head + body);
            const Outcome r = run("run scenes/bad.toml");
            EXPECT_EQ(r.status, 1) << body;
            EXPECT_NE(r.err.find(message), std::string::npos) << body << " -> " << r.err;
            EXPECT_EQ(entries(), std::vector<std::string>{"scenes"}) << body;
        }
    }
};

const char* scene_head = "[scene]\nname = \"demo\"\nexperiment = \"franz\"\ntitle = \"A demo\"\n";

}  // namespace

TEST(MollifyRun, MalformedSceneExits1AndWritesNothing) {
    Workdir w;
    w.file("scenes/bad.toml", "[scene]\nname = \"demo\"\nexperiment = \"franz\"\ntitle = = \"x\"\n");
    Outcome r = w.run("run scenes/bad.toml");
    EXPECT_EQ(r.status, 1);
    EXPECT_EQ(r.err.rfind("mollify: error: scenes/bad.toml:4:", 0), 0u) << r.err;
    EXPECT_EQ(w.entries(), std::vector<std::string>{"scenes"});

    w.file("scenes/unknown.toml", "[scene]\nname = \"demo\"\nexperiment = \"frnz\"\n");
    r = w.run("run scenes/unknown.toml");
    EXPECT_EQ(r.status, 1);
    EXPECT_NE(r.err.find("scenes/unknown.toml:3: scene.experiment = \"frnz\": unknown experiment"), std::string::npos)
        << r.err;
    EXPECT_EQ(w.entries(), std::vector<std::string>{"scenes"});

    r = w.run("run scenes/missing.toml --out results");
    EXPECT_EQ(r.status, 1);
    EXPECT_NE(r.err.find("scenes/missing.toml"), std::string::npos) << r.err;
    EXPECT_EQ(w.entries(), std::vector<std::string>{"scenes"});
}

TEST(MollifyRun, Usage) {
    Workdir w;
    EXPECT_EQ(w.run("").status, 2);
    EXPECT_EQ(w.run("frobnicate").status, 2);
    EXPECT_EQ(w.run("run").status, 2);
    EXPECT_EQ(w.run("run a.toml --bogus").status, 2);
    const Outcome help = w.run("--help");
    EXPECT_EQ(help.status, 0);
    EXPECT_NE(help.out.find("run"), std::string::npos);
    EXPECT_NE(help.out.find("list"), std::string::npos);
    const Outcome run_help = w.run("run --help");
    EXPECT_EQ(run_help.status, 0);
    EXPECT_NE(run_help.out.find("--out"), std::string::npos);
    EXPECT_NE(run_help.out.find("sph-periodic"), std::string::npos);
}

TEST(MollifyRun, List) {
    Workdir w;
    w.file("scenes/a.toml", scene_head);
    w.file("scenes/b.toml", "[scene]\nname = 1\n");
    w.file("scenes/notes.txt", "not a scene");
    const Outcome r = w.run("list");
    EXPECT_EQ(r.status, 0) << r.err;
    for (const char* part : {"franz", "belley", "sph-periodic", "scenes/a.toml", "A demo", "scenes/b.toml", "invalid"})
        EXPECT_NE(r.out.find(part), std::string::npos) << "'" << part << "' not in:\n" << r.out;
    EXPECT_EQ(r.out.find("notes.txt"), std::string::npos);
    // Each experiment's name stands apart from its summary ("poisson-periodic" ran into it).
    std::istringstream experiments(r.out.substr(0, r.out.find("scenes in")));
    int listed = 0;
    for (std::string line; std::getline(experiments, line);)
        if (line != "experiments:") {
            ++listed;
            EXPECT_TRUE(std::regex_match(line, std::regex("  [a-z-]+  +[A-Z0-9a-z].*"))) << "'" << line << "'";
        }
    EXPECT_GE(listed, 7);
    EXPECT_EQ(w.run("list nowhere").status, 1);
}

// `mollify report`: a section that passes, a section that fails (its scene
// is missing from the --scenes folder) reported in its place while the
// others still run, the exit status saying so, and the report written
// atomically in either case. (The whole report runs from the README.)
// Not in the sanitized build (not skipped there: absent): it runs the whole
// generator's emit again (~3.5 min at -O0 + ASan); the emit under ASan is
// Cli.EveryFamilyEmitsAsCheckedInUnderSanitizers.
#ifndef MOLLIFY_SANITIZED_BUILD
TEST(MollifyReport, SectionsPassOrFailIndependently) {
    Workdir w;
    w.file("empty-scenes/README", "no scenes here\n");
    const Outcome r = w.run("report --out rep --only exactness --only studies --scenes empty-scenes");
    EXPECT_EQ(r.status, 1) << r.err;
    const std::string index = slurp(w.dir / "rep" / "index.md");
    EXPECT_NE(index.find("| passed |"), std::string::npos) << index;  // exactness
    EXPECT_NE(index.find("**FAILED** (3)"), std::string::npos) << index;  // three studies, three failures
    EXPECT_NE(index.find("franz_line.toml"), std::string::npos) << index;   // the failure names the missing scene
    const std::size_t all = index.find("| **all** |");                      // every certificate exact and passed:
    ASSERT_NE(all, std::string::npos) << index;                            // "| **all** | kernels | n | n |"
    std::istringstream row(index.substr(all + 11, index.find('\n', all) - all - 11));
    long kernels = 0, checks = -1, passed = -2;
    char bar = 0;
    row >> kernels >> bar >> checks >> bar >> passed;
    EXPECT_GT(kernels, 200);
    EXPECT_EQ(checks, passed) << index;
    EXPECT_NE(index.find("byte for byte"), std::string::npos) << index;
    EXPECT_TRUE(fs::exists(w.dir / "rep" / "exactness" / "errata.csv"));
    EXPECT_TRUE(fs::exists(w.dir / "rep" / "exactness" / "code_errata.csv"));
    EXPECT_NE(index.find("### Errata in published codes"), std::string::npos) << index;
    EXPECT_NE(r.err.find("exactness passed"), std::string::npos) << r.err;  // progress, per section
    EXPECT_NE(r.err.find("studies FAILED"), std::string::npos) << r.err;
    for (const std::string& e : w.entries()) EXPECT_EQ(e.find(".tmp-"), std::string::npos) << e;
}
#endif

TEST(MollifyReport, UnknownSectionIsAnError) {
    Workdir w;
    const Outcome r = w.run("report --only exactnes");
    EXPECT_EQ(r.status, 1);
    EXPECT_NE(r.err.find("unknown report section 'exactnes'"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("exactness, accuracy"), std::string::npos) << r.err;
    EXPECT_EQ(w.entries(), std::vector<std::string>{});
}

// The poisson-free experiment: bad parameters exit 1 naming the value before
// anything is written; a tiny scene writes its tables, plot and summary.
TEST(MollifyRun, PoissonFree) {
    Workdir w;
    const std::string head = "[scene]\nname = \"pf\"\nexperiment = \"poisson-free\"\n[poisson_free]\nparticles = 300\n"
                             "kernels = [\"mollifier:M=4\"]\norders = [2]\n";
    w.file("scenes/bad_delta.toml", head + "delta = -0.5\nthetas = [0.5]\n");
    Outcome r = w.run("run scenes/bad_delta.toml");
    EXPECT_EQ(r.status, 1);
    EXPECT_NE(r.err.find("poisson_free.delta = -0.5"), std::string::npos) << r.err;
    w.file("scenes/bad_theta.toml", head + "delta = 0.1\nthetas = [1.0]\n");
    r = w.run("run scenes/bad_theta.toml");
    EXPECT_EQ(r.status, 1);
    EXPECT_NE(r.err.find("poisson_free.thetas = [1]: opening parameter theta = 1 "), std::string::npos) << r.err;
    // Integers are checked before they narrow to int (orders = [4294967300] had run as p = 4, labelled
    // 4294967300), and the library's checks name the scene's key.
    const std::string good_head = "[scene]\nname = \"pf\"\nexperiment = \"poisson-free\"\n[poisson_free]\nparticles = 300\n"
                                  "kernels = [\"mollifier:M=4\"]\n";
    w.expect_refused(good_head, {
        {"orders = [4294967300]\ndelta = 0.1\nthetas = [0.5]\n", "poisson_free.orders = [4294967300]: 4294967300 is outside 0..20"},
        {"orders = [2]\nleaf_size = 4294967696\ndelta = 0.1\nthetas = [0.5]\n", "poisson_free.leaf_size = 4294967696: 4294967696 is outside"},
        {"orders = [2]\nseed = -1\ndelta = 0.1\nthetas = [0.5]\n", "poisson_free.seed = -1: -1 is negative"},
        {"orders = [2]\ntarget_error = 2\ndelta = 0.1\nthetas = [0.5]\n", "poisson_free.target_error = 2: target relative error 2"},
        {"orders = [2]\ndelta = 1e300\nthetas = [0.5]\n", "poisson_free.delta = 1e+300: smoothing length h = 1e+300 is out of range"},
    });
    w.file("scenes/good.toml", head + "delta = 0.1\nthetas = [0.5]\n");
    r = w.run("run scenes/good.toml");
    EXPECT_EQ(r.status, 0) << r.err;
    for (const char* f : {"results.csv", "tree_0.csv", "time_vs_error.png", "summary.md"})
        EXPECT_TRUE(fs::exists(w.dir / "out" / "pf" / f)) << f;
}

// The Franz experiment: a precision that does not exist, or a checked kernel
// that is not among the scene's, exits 1 naming it before any run and writes
// nothing; a small study in Precision::fast writes its precision check (the
// same kernel in accurate, any spelling of its spec).
#if MOLLIFY_STUDIES
TEST(MollifyRun, FranzPrecisionAndCheckedKernels) {
    Workdir w;
    const std::string head = std::string(scene_head) +
                             "[franz]\ncase = \"torus\"\nk = [1]\nl = [1]\nm = [1, 2]\nepsilon = [0.25, 0.2]\n";
    w.file("scenes/bad_precision.toml", head + "precision = \"exact\"\n");
    Outcome r = w.run("run scenes/bad_precision.toml");
    EXPECT_EQ(r.status, 1);
    EXPECT_NE(r.err.find("franz.precision = \"exact\": unknown precision 'exact'"), std::string::npos) << r.err;
    // An integrator the library does not know, and one eps twice (its rates had been fitted anyway).
    w.file("scenes/bad_integrator.toml", head + "integrator = \"euler\"\n");
    r = w.run("run scenes/bad_integrator.toml");
    EXPECT_EQ(r.status, 1);
    EXPECT_NE(r.err.find("franz.integrator = \"euler\": unknown integrator 'euler'"), std::string::npos) << r.err;
    w.file("scenes/twice.toml", std::string(scene_head) + "[franz]\ncase = \"torus\"\nk = [1]\nl = [1]\nm = [1]\nepsilon = [0.25, 0.2, 0.25]\n");
    r = w.run("run scenes/twice.toml");
    EXPECT_EQ(r.status, 1);
    EXPECT_NE(r.err.find("franz.epsilon = [0.25, 0.2, 0.25]: eps = 0.25 is given twice"), std::string::npos) << r.err;
    // A t_end too short to move anything: Q = 0, no rate to fit (the fit's error had not named t_end).
    w.expect_refused(std::string(scene_head) + "[franz]\ncase = \"torus\"\nk = [1]\nl = [1]\nm = [1]\nepsilon = [0.25, 0.2]\n",
                     {{"t_end = 1e-300\n", "franz.t_end = 1e-300: the rates of wendland:k=1,l=1 over eps: convergence_rate: point"}});
    w.file("scenes/bad_check.toml", head + "precision_check = [\"wendland:k=3\"]\n");
    r = w.run("run scenes/bad_check.toml");
    EXPECT_EQ(r.status, 1);
    EXPECT_NE(r.err.find("kernel 'wendland:k=3' is not among the scene's kernels"), std::string::npos) << r.err;
    EXPECT_EQ(w.entries(), std::vector<std::string>{"scenes"});
    // A short run (t_end 0.1, not 0.8): the test is about the two settings, and
    // under the sanitizers the default run took 31 s.
    w.file("scenes/good.toml",
           head + "t_end = 0.1\nprecision = \"fast\"\nprecision_check = [\"wendland:l=1,k=1\"]\n");
    r = w.run("run scenes/good.toml");
    ASSERT_EQ(r.status, 0) << r.err;
    const std::string check = slurp(w.dir / "out" / "demo" / "precision_check.csv");
    EXPECT_NE(check.find("Q_kin (fast),Q_kin (accurate)"), std::string::npos) << check;
    EXPECT_NE(check.find("\"wendland:k=1,l=1\",0.2,"), std::string::npos) << check;
}
#else
// A mollify built without the studies (-DMOLLIFY_STUDIES=OFF: CI's sanitizer
// build) still lists them, and running one exits 1 saying why, writing nothing.
TEST(MollifyRun, StudiesLeftOutSayHowToGetThem) {
    Workdir w;
    for (const char* study : {"franz", "belley"}) {
        w.file("scenes/study.toml", std::string("[scene]\nname = \"demo\"\nexperiment = \"") + study + "\"\n");
        const Outcome r = w.run("run scenes/study.toml");
        EXPECT_EQ(r.status, 1) << study;
        EXPECT_NE(r.err.find(std::string("scene.experiment = \"") + study + "\""), std::string::npos) << r.err;
        EXPECT_NE(r.err.find("-DMOLLIFY_STUDIES=ON"), std::string::npos) << r.err;
        EXPECT_EQ(w.entries(), std::vector<std::string>{"scenes"});
    }
}
#endif

// The vortex-sheet experiment: bad parameters exit 1 naming the value before
// anything is written; a tiny sheet writes its positions, pictures, summary.
TEST(MollifyRun, VortexSheet) {
    Workdir w;
    const std::string head = "[scene]\nname = \"vs\"\nexperiment = \"vortex-sheet\"\n[vortex_sheet]\nparticles = 24\n"
                             "times = [0.1, 0.2]\n";
    w.file("scenes/bad_delta.toml", head + "algebraic_delta = -0.25\ndt = 0.05\n");
    Outcome r = w.run("run scenes/bad_delta.toml");
    EXPECT_EQ(r.status, 1);
    EXPECT_NE(r.err.find("vortex_sheet.algebraic_delta = -0.25"), std::string::npos) << r.err;
    w.file("scenes/bad_support.toml", head + "kernels = [\"wendland:k=2\"]\nsupport = 0.7\ndt = 0.05\n");
    r = w.run("run scenes/bad_support.toml");
    EXPECT_EQ(r.status, 1);
    EXPECT_NE(r.err.find("vortex_sheet.support = 0.7"), std::string::npos) << r.err;
    // A time of more steps than a scene may run (1e30 / 0.05 had overflowed the step count).
    w.expect_refused("[scene]\nname = \"vs\"\nexperiment = \"vortex-sheet\"\n[vortex_sheet]\nparticles = 24\n",
                     {{"times = [0.1, 1e30]\nalgebraic_delta = 0.25\ndt = 0.05\n",
                       "vortex_sheet.times = [0.1, 1e+30]: 1e+30 in steps dt = 0.05 takes 2e+31 steps, more than the 10^7"}});
    w.file("scenes/bad_steps.toml", head + "algebraic_delta = 0.25\ndt = 0.03\n");
    r = w.run("run scenes/bad_steps.toml");
    EXPECT_EQ(r.status, 1);
    EXPECT_NE(r.err.find("not a whole number of steps dt = 0.03"), std::string::npos) << r.err;
    // The treecode: compact blobs only, its knobs only with it, its range.
    w.file("scenes/tree_algebraic.toml", head + "summation = \"treecode\"\nalgebraic_delta = 0.25\ndt = 0.05\n");
    r = w.run("run scenes/tree_algebraic.toml");
    EXPECT_EQ(r.status, 1);
    EXPECT_NE(r.err.find("vortex_sheet.algebraic_delta = 0.25: Krasny's algebraic blob is not compact"), std::string::npos) << r.err;
    w.file("scenes/direct_theta.toml", head + "treecode_theta = 0.5\nalgebraic_delta = 0.25\ndt = 0.05\n");
    r = w.run("run scenes/direct_theta.toml");
    EXPECT_EQ(r.status, 1);
    EXPECT_NE(r.err.find("vortex_sheet.treecode_theta"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("summation is \"direct\""), std::string::npos) << r.err;
    w.file("scenes/tree_order.toml", head + "summation = \"treecode\"\ntreecode_order = 50\nkernels = [\"wendland:k=2\"]\nsupport = 0.1\ndt = 0.05\n");
    r = w.run("run scenes/tree_order.toml");
    EXPECT_EQ(r.status, 1);
    EXPECT_NE(r.err.find("vortex_sheet.treecode_order = 50"), std::string::npos) << r.err;
    w.file("scenes/bad_summation.toml", head + "summation = \"fmm\"\nalgebraic_delta = 0.25\ndt = 0.05\n");
    r = w.run("run scenes/bad_summation.toml");
    EXPECT_EQ(r.status, 1);
    EXPECT_NE(r.err.find("vortex_sheet.summation = \"fmm\""), std::string::npos) << r.err;
    EXPECT_EQ(w.entries(), std::vector<std::string>{"scenes"});
    w.file("scenes/tree.toml", "[scene]\nname = \"vt\"\nexperiment = \"vortex-sheet\"\n[vortex_sheet]\nparticles = 300\ntimes = [0.1]\n"
                               "summation = \"treecode\"\nkernels = [\"wendland:k=2\"]\nsupport = 0.05\ndt = 0.05\n");
    r = w.run("run scenes/tree.toml");
    EXPECT_EQ(r.status, 0) << r.err;
    EXPECT_TRUE(fs::exists(w.dir / "out" / "vt" / "sheet_0.csv"));
    std::ifstream summary(w.dir / "out" / "vt" / "summary.md");
    const std::string md((std::istreambuf_iterator<char>(summary)), std::istreambuf_iterator<char>());
    EXPECT_NE(md.find("the periodic treecode (θ = 0.4, order 20"), std::string::npos) << md;
    w.file("scenes/good.toml", head + "algebraic_delta = 0.25\nkernels = [\"mollifier:M=4\"]\nsupport = 0.25\ndt = 0.05\n");
    r = w.run("run scenes/good.toml");
    EXPECT_EQ(r.status, 0) << r.err;
    for (const char* f : {"sheet_0.csv", "sheet_1.csv", "sheet_0.png", "sheet_1.png", "sheets_last.png", "summary.md"})
        EXPECT_TRUE(fs::exists(w.dir / "out" / "vs" / f)) << f;
}

// The sph-periodic experiment: a CFL number outside (0, 1] and runs of more
// steps than a scene may take (a far snapshot; an amplitude whose sound
// speed makes the steps ~1e-157: it had run for ever) exit 1 naming the
// value before anything is written; a small lattice runs.
TEST(MollifyRun, SphPeriodic) {
    Workdir w;
    const std::string head = "[scene]\nname = \"sp\"\nexperiment = \"sph-periodic\"\n[sph_periodic]\ndim = 2\n"
                             "kernel = \"wendland:k=2\"\nparticles_per_side = 12\neps_over_h = 3.0\nwidth = 0.1\n"
                             "precision = \"fast\"\n";
    w.expect_refused(head, {
        {"cfl = nan\namplitude = 0.5\nsnapshots = [0.0, 0.01]\n", "sph_periodic.cfl = nan: nan is not in (0, 1]"},
        {"cfl = 1.5\namplitude = 0.5\nsnapshots = [0.0, 0.01]\n", "sph_periodic.cfl = 1.5: 1.5 is not in (0, 1]"},
        {"cfl = 0.1\namplitude = 0.5\nsnapshots = [0.0, 1e9]\n", "more than the 10^7 a scene may run"},
        {"cfl = 0.1\namplitude = 1e308\nsnapshots = [0.0, 0.01]\n", "(amplitude 1e+308, CFL 0.1) takes "},
    });
    w.file("scenes/good.toml", head + "cfl = 0.1\namplitude = 0.5\nsnapshots = [0.0, 0.01]\n");
    const Outcome r = w.run("run scenes/good.toml");
    EXPECT_EQ(r.status, 0) << r.err;
    for (const char* f : {"history.csv", "snapshot_1.csv", "summary.md"}) EXPECT_TRUE(fs::exists(w.dir / "out" / "sp" / f)) << f;
}

// The poisson-periodic experiment: bad parameters exit 1 naming the value
// before anything is written; a small scene writes its tables and plots.
TEST(MollifyRun, PoissonPeriodic) {
    Workdir w;
    const std::string head = "[scene]\nname = \"pp\"\nexperiment = \"poisson-periodic\"\n[poisson_periodic]\nbvp_sizes = [8, 16]\n"
                             "particles_per_side = 32\nkernels = [\"wendland:k=2\"]\n";
    w.file("scenes/bad_sigma.toml", head + "bvp_sigma = -2.5\ngrids = [8]\n");
    Outcome r = w.run("run scenes/bad_sigma.toml");
    EXPECT_EQ(r.status, 1);
    EXPECT_NE(r.err.find("poisson_periodic.bvp_sigma = -2.5"), std::string::npos) << r.err;
    w.file("scenes/bad_grid.toml", head + "bvp_sigma = 2.5\ngrids = [1]\n");
    r = w.run("run scenes/bad_grid.toml");
    EXPECT_EQ(r.status, 1);
    EXPECT_NE(r.err.find("1 points per axis"), std::string::npos) << r.err;
    // The library's checks and the support against the grid, named with the scene's keys.
    w.expect_refused(head, {
        {"bvp_sigma = 1e300\ngrids = [8]\n", "poisson_periodic.bvp_sigma = 1e+300: periodic BVP: sigma = 1e+300 is not in (0, 700]"},
        {"bvp_sigma = 2.5\ngrids = [8, 16]\ndelta_cells = 4.5\n",
         "poisson_periodic.delta_cells = 4.5: 4.5 grid spacings of the 8-point grid are not below half the box"},
    });
    EXPECT_EQ(w.entries(), std::vector<std::string>{"scenes"});
    w.file("scenes/good.toml", head + "bvp_sigma = 2.5\ngrids = [8, 16]\n");
    r = w.run("run scenes/good.toml");
    EXPECT_EQ(r.status, 0) << r.err;
    for (const char* f : {"bvp.csv", "bvp.png", "pic.csv", "pic.png", "summary.md"}) EXPECT_TRUE(fs::exists(w.dir / "out" / "pp" / f)) << f;
}

// A scene naming kernels outside the compiled catalogue runs from a fresh
// build without recompiling: they are generated exactly and cached on the
// first run, read from the cache on the second, and the values written are
// the exact ones (mollify-gen value, 40 digits) to within 4 ulp (the runtime's
// accuracy bound, tests/accuracy_test.cpp).
TEST(MollifyRun, KernelsOutsideTheCatalogue) {
    Workdir w;
    w.file("scenes/k.toml",
           "[scene]\nname = \"k\"\nexperiment = \"kernel-values\"\n[kernel_values]\n"
           "kernels = [\"wendland:k=6,l=3\", \"combo:radii=1/4;1/2;1,base=mollifier:M=5\"]\n"
           "dim = 3\nquantities = [\"value\", \"potential\"]\nradii = [0.5, 0.875]\nh = 1.0\n");
    const std::string env = "MOLLIFY_CACHE_DIR='" + (w.dir / "cache").string() + "' ";
    auto run = [&] {
        return mollify::testing::run_command("cd '" + w.dir.string() + "' && " + env + MOLLIFY + " run scenes/k.toml",
                                             w.dir / ".run");
    };
    Outcome r = run();
    ASSERT_EQ(r.status, 0) << r.err;
    std::size_t cached = 0;
    for (const auto& e : fs::recursive_directory_iterator(w.dir / "cache")) cached += e.is_regular_file();
    EXPECT_EQ(cached, 2u);
    const std::string first = slurp(w.dir / "out/k/values.csv");
    r = run();
    ASSERT_EQ(r.status, 0) << r.err;
    EXPECT_EQ(slurp(w.dir / "out/k/values.csv"), first);  // from the cache: the same doubles

    std::istringstream lines(first);
    std::string line;
    std::getline(lines, line);
    EXPECT_EQ(line, "spec,dim,quantity,h,r,value");
    int checked = 0;
    while (std::getline(lines, line)) {
        // spec may hold commas (quoted): the last four fields from the right.
        std::vector<std::string> f;
        std::size_t end = line.size();
        for (int i = 0; i < 4; ++i) {
            const std::size_t comma = line.rfind(',', end - 1);
            f.insert(f.begin(), line.substr(comma + 1, end - comma - 1));
            end = comma;
        }
        std::string spec = line.substr(0, line.rfind(',', end - 1));
        if (spec.front() == '"') spec = spec.substr(1, spec.size() - 2);
        const std::string& quantity = f[0];
        const double r_value = std::stod(f[2]), value = std::stod(f[3]);
        const std::string r_text = r_value == 0.5 ? "1/2" : "7/8";
        const Outcome exact = mollify::testing::run_command(std::string(MOLLIFY_GEN) + " value '" + spec +
                                                                "' --dim 3 --r " + r_text + " --quantity " + quantity,
                                                            w.dir / ".gen");
        ASSERT_EQ(exact.status, 0) << exact.err;
        const double e = std::stod(exact.out);
        EXPECT_LE(std::abs(value - e), 4 * std::ldexp(1.0, std::ilogb(e) - 52)) << spec << " " << quantity << " at " << r_text;
        ++checked;
    }
    EXPECT_EQ(checked, 8);
}

// A kernel-values scene with an empty list is refused naming the key (it had
// run and written empty tables), and nothing is written.
TEST(MollifyRun, KernelValuesEmptyListsAreRefused) {
    Workdir w;
    const std::string head = "[scene]\nname = \"k\"\nexperiment = \"kernel-values\"\n[kernel_values]\ndim = 3\nh = 1.0\n";
    w.expect_refused(head, {
        {"kernels = []\nradii = [0.5]\n", "kernel_values.kernels = []: no kernel"},
        {"kernels = [\"wendland:k=2\"]\nradii = []\n", "kernel_values.radii = []: no radius"},
        {"kernels = [\"wendland:k=2\"]\nradii = [0.5]\nquantities = []\n", "kernel_values.quantities = []: no quantity"},
    });
    // An h the runtime refuses, named with the scene's key before any value (it had failed without them).
    w.expect_refused("[scene]\nname = \"k\"\nexperiment = \"kernel-values\"\n[kernel_values]\ndim = 3\n",
                     {{"h = 1e300\nkernels = [\"wendland:k=2\"]\nradii = [0.5]\n",
                       "kernel_values.h = 1e+300: smoothing length h = 1e+300 is out of range in D = 3"}});
}
