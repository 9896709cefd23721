// The mollify app's infrastructure (tools/mollify): scene files and their
// errors (each names the file, the key or value, the line), the atomic output
// folder, tables, gnuplot, progress.
#include "experiment.hpp"
#include "output.hpp"
#include "scene.hpp"

#include <mollify/error.hpp>

#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include <fcntl.h>
#include <unistd.h>

namespace fs = std::filesystem;
using namespace mollify::app;

namespace {

const char* good = R"(# a scene
[scene]
name = "franz-torus"
experiment = "franz"
title = "Franz 6.2.2 on the torus"

[franz]
epsilon = [0.25, 0.2, 1]
kernels = ["wendland:k=2", "wendland:k=3"]
steps = 1e4
dims = [1, 3]
t = 0.8
rk4 = true
name = "x"
bad = "text"
zero = 0
negative = -1.5
nan = nan
)";

// The Error message of f(), or "" if it did not throw one.
template <class F>
std::string error_of(F f) {
    try {
        f();
    } catch (const mollify::Error& e) {
        return e.what();
    }
    return "";
}

#define EXPECT_ERROR(expr, ...)                                                  \
    do {                                                                         \
        const std::string message = error_of([&] { (void)(expr); });             \
        ASSERT_FALSE(message.empty()) << #expr " did not throw mollify::Error"; \
        for (const char* part : {__VA_ARGS__})                                   \
            EXPECT_NE(message.find(part), std::string::npos)                     \
                << "message '" << message << "' lacks '" << part << "'";         \
    } while (0)

// A fresh empty folder, removed at the end of the test.
struct Scratch {
    fs::path dir;
    Scratch() {
        std::string t = (fs::temp_directory_path() / "mollify-scene-test-XXXXXX").string();
        dir = ::mkdtemp(t.data());
    }
    ~Scratch() { fs::remove_all(dir); }
    std::vector<std::string> entries() const {
        std::vector<std::string> v;
        for (const auto& e : fs::directory_iterator(dir)) v.push_back(e.path().filename().string());
        std::sort(v.begin(), v.end());
        return v;
    }
};

std::string slurp(const fs::path& p) {
    std::ifstream f(p, std::ios::binary);
    std::ostringstream s;
    s << f.rdbuf();
    return s.str();
}

Scene scene(const std::string& franz_section) {
    return Scene::parse("[scene]\nname = \"s\"\nexperiment = \"franz\"\n[franz]\n" + franz_section, "test.toml");
}

}  // namespace

TEST(Scene, ParsesAGoodScene) {
    const Scene s = Scene::parse(good, "good.toml");
    EXPECT_EQ(s.origin(), "good.toml");
    EXPECT_EQ(s.name(), "franz-torus");
    EXPECT_EQ(s.experiment(), "franz");
    EXPECT_EQ(s.title(), "Franz 6.2.2 on the torus");
    EXPECT_EQ(s.text(), good);
    EXPECT_TRUE(s.has("franz.epsilon"));
    EXPECT_FALSE(s.has("franz.missing"));
    EXPECT_EQ(s.numbers("franz.epsilon"), (std::vector<double>{0.25, 0.2, 1.0}));
    EXPECT_EQ(s.strings("franz.kernels"), (std::vector<std::string>{"wendland:k=2", "wendland:k=3"}));
    EXPECT_EQ(s.integer("franz.steps"), 10000);  // an exactly integral float is an integer
    EXPECT_EQ(s.integers("franz.dims"), (std::vector<long>{1, 3}));
    EXPECT_EQ(s.number("franz.t"), 0.8);
    EXPECT_EQ(s.number("franz.dims[1]"), 3.0);  // integers convert to double
    EXPECT_EQ(s.positive("franz.t"), 0.8);
    EXPECT_TRUE(s.boolean("franz.rk4", false));
    EXPECT_EQ(s.string("franz.name"), "x");
    EXPECT_EQ(s.number("franz.h", 0.5), 0.5);
    EXPECT_EQ(s.integer("franz.n", 7), 7);
    EXPECT_EQ(s.string("franz.spec", "poly6"), "poly6");
    EXPECT_FALSE(s.boolean("franz.leapfrog", false));
    EXPECT_NO_THROW(s.only("franz", {"epsilon", "kernels", "steps", "dims", "t", "rk4", "name", "bad", "zero",
                                     "negative", "nan"}));
    EXPECT_EQ(find_experiment(s).name, "franz");
}

TEST(Scene, TitleDefaultsToName) {
    EXPECT_EQ(scene("").title(), "s");
}

TEST(Scene, MissingFile) {
    EXPECT_ERROR(Scene::load("/nonexistent/nope.toml"), "/nonexistent/nope.toml", "cannot read");
}

TEST(Scene, LoadsAFile) {
    Scratch tmp;
    const fs::path f = tmp.dir / "a.toml";
    std::ofstream(f) << good;
    EXPECT_EQ(Scene::load(f).origin(), f.string());
    EXPECT_EQ(Scene::load(f).name(), "franz-torus");
}

TEST(Scene, SyntaxErrorNamesTheLine) {
    EXPECT_ERROR(Scene::parse("[scene]\nname = \"s\"\nexperiment = = 3\n", "bad.toml"), "bad.toml:3:",
                 "TOML syntax error");
    EXPECT_ERROR(Scene::parse("[scene]\nname = \"s\"\nname = \"t\"\n", "dup.toml"), "dup.toml:3:");
}

TEST(Scene, SceneTableIsRequired) {
    EXPECT_ERROR(Scene::parse("[franz]\nx = 1\n", "a.toml"), "a.toml", "[scene]");
    EXPECT_ERROR(Scene::parse("[scene]\nname = \"s\"\n", "a.toml"), "a.toml", "missing key scene.experiment");
    EXPECT_ERROR(Scene::parse("[scene]\nexperiment = \"franz\"\n", "a.toml"), "missing key scene.name");
    EXPECT_ERROR(Scene::parse("scene = 3\n", "a.toml"), "a.toml:1", "scene", "expected a table");
    EXPECT_ERROR(Scene::parse("[scene]\nname = 3\nexperiment = \"franz\"\n", "a.toml"), "a.toml:2",
                 "scene.name = 3", "expected a string, got an integer");
}

TEST(Scene, NameMustBeAFolderName) {
    for (const char* name : {"../up", "a/b", "", ".hidden", "-x", "a b"})
        EXPECT_ERROR(Scene::parse(std::string("[scene]\nname = \"") + name + "\"\nexperiment = \"franz\"\n", "n.toml"),
                     "n.toml:2", "scene.name", "folder name");
}

TEST(Scene, UnknownKeyInSceneTable) {
    EXPECT_ERROR(Scene::parse("[scene]\nname = \"s\"\nexperiment = \"franz\"\ntitel = \"x\"\n", "u.toml"), "u.toml:4",
                 "unknown key scene.titel", "title");
}

TEST(Scene, MissingKey) {
    const Scene s = scene("t = 1\n");
    EXPECT_ERROR(s.number("franz.epsilon"), "test.toml", "missing key franz.epsilon");
    EXPECT_ERROR(s.numbers("franz.epsilon"), "missing key franz.epsilon");
    EXPECT_ERROR(s.string("belley.spec"), "missing key belley.spec");
}

TEST(Scene, WrongType) {
    const Scene s = scene("t = \"soon\"\neps = [0.1, \"x\"]\nn = 2.5\nflag = 1\nlist = 3\n");
    EXPECT_ERROR(s.number("franz.t"), "test.toml:5", "franz.t = \"soon\"", "expected a number, got a string");
    EXPECT_ERROR(s.numbers("franz.eps"), "test.toml:6", "franz.eps[1] = \"x\"", "expected a number");
    EXPECT_ERROR(s.integer("franz.n"), "test.toml:7", "franz.n = 2.5", "expected an integer");
    EXPECT_ERROR(s.boolean("franz.flag", false), "test.toml:8", "franz.flag = 1", "boolean");
    EXPECT_ERROR(s.numbers("franz.list"), "test.toml:9", "franz.list = 3", "expected an array of numbers");
    EXPECT_ERROR(s.string("franz.n"), "test.toml:7", "expected a string, got a floating-point number");
    EXPECT_ERROR(s.number("franz"), "test.toml:4", "franz", "got a table");
}

// Found by fuzz/fuzz_scene.cpp: toml++'s formatter is undefined behaviour
// (UBSan) on floats below 0.1; the messages format values themselves.
TEST(Scene, ArraysAndTablesOfSmallNumbersInMessages) {
    const Scene s = scene("eps = [0.05, 1e-300, -0.001]\n[franz.sub]\nx = 0.01\ny = [true, 2]\n");
    EXPECT_ERROR(s.number("franz.eps"), "franz.eps = [0.05, 1e-300, -0.001]", "expected a number, got an array");
    EXPECT_ERROR(s.positive("franz.eps"), "franz.eps = [0.05, 1e-300, -0.001]");
    EXPECT_ERROR(s.string("franz.sub.y"), "franz.sub.y = [true, 2]", "expected a string");
}

// Found by fuzz/fuzz_scene.cpp: toml++ 3.3.0 is undefined behaviour when it
// classifies U+00A1..U+0499 as whitespace or not (keys, between tokens);
// non-ASCII text stays allowed in comments and string values.
TEST(Scene, NonAsciiOutsideStringValuesNamedBeforeToml) {
    EXPECT_NO_THROW(scene("# ε² § comment\nt = \"Franz §6.2.2, h = ε²/10\"\nu = 'ü'\nv = [\"é\", { w = \"ß\" }]\n"
                          "m = \"\"\"\nα\\\"β\n\"\"\"\nl = \'\'\'\nγ\'\'\'\n"));
    EXPECT_ERROR(scene("t = 1§\n"), "test.toml:5", "non-ASCII character outside a string or comment");
    EXPECT_ERROR(scene("§t = 1\n"), "test.toml:5", "non-ASCII character outside a string or comment");
    EXPECT_ERROR(scene("\"ключ\" = 1\n"), "test.toml:5", "non-ASCII character in a key");
    EXPECT_ERROR(scene("v = { \"é\" = 1 }\n"), "test.toml:5", "non-ASCII character in a key");
    EXPECT_ERROR(scene("a = 1\n[\"ü\"]\n"), "test.toml:6", "non-ASCII character in a key");
    EXPECT_ERROR(scene("m = \"\"\"x\\\n  ¡\"\"\"\n"), "test.toml:6", "line-ending backslash");
    // A quote where TOML has no string, a bad value before one: toml++ would
    // read the rest as one bad value, its non-ASCII characters classified too
    // (the fuzzer's finds); the structure is parsed first, with placeholders.
    EXPECT_ERROR(scene("x = 0\"§\"\n"), "test.toml:5", "TOML syntax error");
    EXPECT_ERROR(scene("x = [0.3, 0\"ε\"]\n"), "test.toml:5", "TOML syntax error");
    EXPECT_ERROR(scene("x = \"a\"\"§\"\n"), "test.toml:5", "TOML syntax error");
    EXPECT_ERROR(scene("kerns = -[\"mo\xef\xbf\xbe\"]\n"), "test.toml:5", "TOML syntax error");
    EXPECT_NO_THROW(scene("\"a\".\"b\" = [ \"§\" , {c = \"é\"} ]\n[\"d\"]\n'e' = '''ü'''\n"));
}

TEST(Scene, NonPositiveNumber) {
    const Scene s = Scene::parse(good, "good.toml");
    EXPECT_ERROR(s.positive("franz.zero"), "good.toml:16", "franz.zero = 0", "positive");
    EXPECT_ERROR(s.positive("franz.negative"), "good.toml:17", "franz.negative = -1.5", "positive");
    EXPECT_ERROR(s.positive("franz.nan"), "good.toml:18", "franz.nan = nan", "positive");
    EXPECT_ERROR(s.reject("franz.t", "too small for the spacing"), "good.toml:12", "franz.t = 0.8",
                 "too small for the spacing");
    EXPECT_ERROR(s.reject("franz.absent", "needed"), "good.toml", "franz.absent", "needed");
}

TEST(Scene, UnknownKeysViaOnly) {
    const Scene s = scene("epsilon = 1\nepsilom = 2\nh = 3\n");
    EXPECT_ERROR(s.only("franz", {"epsilon", "h"}), "test.toml:6", "unknown key franz.epsilom", "epsilon, h");
    EXPECT_NO_THROW(s.only("belley", {"x"}));  // an absent section has no unknown keys
    EXPECT_ERROR(s.only("franz.h", {}), "franz.h", "expected a table");
}

TEST(Scene, UnknownExperiment) {
    const Scene s = Scene::parse("[scene]\nname = \"s\"\nexperiment = \"frnz\"\n", "e.toml");
    EXPECT_ERROR(find_experiment(s), "e.toml:3", "scene.experiment = \"frnz\"", "unknown experiment", "franz",
                 "belley", "sph-periodic");
}

TEST(Experiments, Registry) {
    std::vector<std::string> names;
    for (const Experiment& e : experiments()) {
        names.emplace_back(e.name);
        EXPECT_FALSE(e.summary.empty());
        EXPECT_NE(e.run, nullptr);
    }
    EXPECT_EQ(names, (std::vector<std::string>{"franz", "belley", "sph-periodic", "poisson-free", "poisson-periodic",
                                              "vortex-sheet", "kernel-values"}));
}

TEST(Table, CsvQuotingAndMarkdown) {
    Table t{{"kernel", "note", "rate"}, {}};
    t.add({"wendland:k=2,l=1", "say \"hi\"", "1.5"});
    t.add({"plain", "two\nlines", "2"});
    EXPECT_EQ(t.csv(), "kernel,note,rate\n\"wendland:k=2,l=1\",\"say \"\"hi\"\"\",1.5\nplain,\"two\nlines\",2\n");
    t.rows.clear();
    t.add({"a|b", "x", "1"});
    EXPECT_EQ(t.markdown(), "| kernel | note | rate |\n|---|---|---|\n| a\\|b | x | 1 |\n");
    EXPECT_ERROR(t.add({"too", "short"}), "2 cells", "3 columns");
}

TEST(Format, Numbers) {
    EXPECT_EQ(format(0.123456789), "0.1235");
    EXPECT_EQ(format(1.0 / 3, 2), "0.33");
    EXPECT_EQ(format(1e-20, 3), "1e-20");
    EXPECT_EQ(format(std::nan("")), "nan");
    EXPECT_EQ(format(-std::nan("")), "nan");
    EXPECT_EQ(format(-HUGE_VAL), "-inf");
    EXPECT_EQ(format(HUGE_VAL), "inf");
}

TEST(Output, CommitIsAtomic) {
    Scratch tmp;
    const fs::path dest = tmp.dir / "run";
    {
        Output out(dest);
        EXPECT_EQ(out.destination(), dest);
        EXPECT_EQ(out.staging().parent_path(), tmp.dir);
        EXPECT_EQ(out.staging().filename().string().rfind("run.tmp-", 0), 0u);
        out.write("a.csv", "x\n1\n");
        out.write("sub/b.txt", "b");
        out.summary() += "# run\n";
        EXPECT_FALSE(fs::exists(dest));  // nothing visible before commit
        out.commit();
        EXPECT_ERROR(out.write("late.txt", ""), "already committed");
    }
    EXPECT_EQ(tmp.entries(), std::vector<std::string>{"run"});  // no staging or temporary left
    EXPECT_EQ(slurp(dest / "a.csv"), "x\n1\n");
    EXPECT_EQ(slurp(dest / "sub/b.txt"), "b");
    EXPECT_EQ(slurp(dest / "summary.md"), "# run\n");

    {  // a second commit replaces the folder as a whole
        Output out(dest);
        out.write("c.csv", "c");
        out.commit();
    }
    EXPECT_EQ(tmp.entries(), std::vector<std::string>{"run"});
    EXPECT_FALSE(fs::exists(dest / "a.csv"));
    EXPECT_EQ(slurp(dest / "c.csv"), "c");
}

TEST(Output, AbandonedOutputKeepsThePreviousFolder) {
    Scratch tmp;
    const fs::path dest = tmp.dir / "run";
    {
        Output out(dest);
        out.write("a.csv", "old");
        out.commit();
    }
    EXPECT_ERROR(([&] {
                     Output out(dest);
                     out.write("a.csv", "new, half-written");
                     EXPECT_TRUE(fs::exists(out.staging()));
                     mollify::fail("the run failed");
                 }()),
                 "the run failed");
    EXPECT_EQ(tmp.entries(), std::vector<std::string>{"run"});  // staging removed
    EXPECT_EQ(slurp(dest / "a.csv"), "old");
    EXPECT_EQ(slurp(dest / "summary.md"), "");

    {  // never committed, nothing existed: nothing is left, not even the parent it made
        Output out(tmp.dir / "new" / "other");
        EXPECT_TRUE(fs::is_directory(tmp.dir / "new"));
    }
    EXPECT_EQ(tmp.entries(), std::vector<std::string>{"run"});
}

TEST(Output, BadNames) {
    Scratch tmp;
    Output out(tmp.dir / "run");
    for (const char* name : {"../escape.csv", "a/../../b", "/etc/x", "", ".", "dir/"})
        EXPECT_ERROR(out.write(name, "x"), "output file name", name);
    EXPECT_ERROR(out.plot("../x.png", "plot x"), "../x.png");
    EXPECT_FALSE(fs::exists(tmp.dir / "escape.csv"));
    EXPECT_ERROR(Output(tmp.dir / ".."), "..");
    std::ofstream(tmp.dir / "file") << "x";
    EXPECT_ERROR(Output(tmp.dir / "file"), "not a folder");
}

TEST(Output, CreatesParentFolders) {
    Scratch tmp;
    {
        Output out(tmp.dir / "out" / "deep" / "run/");
        EXPECT_EQ(out.destination(), tmp.dir / "out" / "deep" / "run");
        out.commit();
    }
    EXPECT_TRUE(fs::is_regular_file(tmp.dir / "out/deep/run/summary.md"));
}

bool have_gnuplot() { return std::system("gnuplot --version >/dev/null 2>&1") == 0; }

// gnuplot is a dependency of the app (tools/install-deps.sh installs
// gnuplot-nox, CI runs it): without it this test fails rather than skips, so
// the PNG path is never silently untested.
TEST(Output, GnuplotWritesAPng) {
    ASSERT_TRUE(have_gnuplot()) << "gnuplot is not installed (tools/install-deps.sh installs gnuplot-nox)";
    Scratch tmp;
    {
        Output out(tmp.dir / "run");
        Table t{{"x", "y"}, {}};
        for (int i = 1; i <= 10; ++i) t.add({format(i), format(i * i)});
        out.csv("data.csv", t);
        out.plot("square.png", "set logscale xy\nplot 'data.csv' using 1:2 with linespoints\n", 300, 200);
        EXPECT_ERROR(out.plot("broken.png", "plot 'data.csv' using 1:2\nplot nonsense(\n"), "broken.png",
                     "gnuplot failed", "broken.png.gp\" line 2");
        EXPECT_FALSE(fs::exists(out.staging() / "broken.png"));
        out.commit();
    }
    const std::string png = slurp(tmp.dir / "run/square.png");
    ASSERT_GT(png.size(), 8u);
    EXPECT_EQ(png.substr(1, 3), "PNG");
    std::vector<std::string> files;
    for (const auto& e : fs::directory_iterator(tmp.dir / "run")) files.push_back(e.path().filename().string());
    std::sort(files.begin(), files.end());
    EXPECT_EQ(files, (std::vector<std::string>{"data.csv", "square.png", "summary.md"}));  // no temporaries, no scripts
}

TEST(Output, MissingGnuplotIsAClearError) {
    Scratch tmp;
    const char* old = std::getenv("PATH");
    const std::string saved = old ? old : "";
    ::setenv("PATH", tmp.dir.c_str(), 1);
    Output out(tmp.dir / "run");
    const std::string message = error_of([&] { out.plot("a.png", "plot x"); });
    ::setenv("PATH", saved.c_str(), 1);
    EXPECT_NE(message.find("gnuplot is not installed"), std::string::npos) << message;
    EXPECT_NE(message.find("tools/install-deps.sh"), std::string::npos) << message;
}

// Standard error (file descriptor 2, which std::cerr writes to) redirected to
// a file while alive. A file is not a terminal, so progress() takes its
// one-line-per-call path; it decides that once per process, at its first
// call, which must therefore happen inside the capture (no other test here
// calls it).
class CapturedStderr {
public:
    explicit CapturedStderr(fs::path file) : file_(std::move(file)) {
        std::cerr.flush();
        saved_ = ::dup(STDERR_FILENO);
        const int fd = ::open(file_.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0600);
        if (saved_ < 0 || fd < 0 || ::dup2(fd, STDERR_FILENO) < 0)
            throw std::runtime_error("cannot redirect stderr to " + file_.string());
        ::close(fd);
    }
    CapturedStderr(const CapturedStderr&) = delete;
    CapturedStderr& operator=(const CapturedStderr&) = delete;
    ~CapturedStderr() {
        std::cerr.flush();
        ::dup2(saved_, STDERR_FILENO);
        ::close(saved_);
    }
    std::string text() const {
        std::cerr.flush();
        return slurp(file_);
    }

private:
    fs::path file_;
    int saved_ = -1;
};

std::vector<std::string> lines_of(const std::string& text) {
    std::vector<std::string> lines;
    std::istringstream in(text);
    for (std::string line; std::getline(in, line);) lines.push_back(line);
    return lines;
}

// Into a log file: the first call, then at most one line a second, and the
// final call (done == total) always; after it the next stage shows at once.
// The bound on the lines in between comes from the loop's measured duration,
// so a slow machine cannot fail it; a progress() that printed every call
// (1001 lines in well under a second) or dropped the final line fails.
TEST(Progress, LogFileGetsFirstRateLimitedAndFinalLines) {
    Scratch tmp;
    std::string text;
    double seconds = 0;
    {
        const CapturedStderr err(tmp.dir / "stderr.log");
        const auto start = std::chrono::steady_clock::now();
        for (std::size_t i = 0; i <= 1000; ++i) progress("test", i, 1000, "step");
        seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        progress("next", 0, 2);
        progress_clear();  // no in-place line in a file: writes nothing
        text = err.text();
    }
    EXPECT_EQ(text.find('\r'), std::string::npos) << "in-place rewriting in a file";
    ASSERT_FALSE(text.empty());
    EXPECT_EQ(text.back(), '\n');
    const std::vector<std::string> lines = lines_of(text);
    ASSERT_GE(lines.size(), 3u) << text;
    EXPECT_EQ(lines.front(), "[test] 0/1000 step");
    EXPECT_EQ(lines[lines.size() - 2], "[test] 1000/1000 step");
    EXPECT_EQ(lines.back(), "[next] 0/2");
    const std::size_t between = lines.size() - 3;
    EXPECT_LE(between, static_cast<std::size_t>(seconds)) << text;
    std::size_t last = 0;
    for (std::size_t i = 1; i + 2 < lines.size(); ++i) {
        const std::string& l = lines[i];
        const std::string head = "[test] ", tail = "/1000 step";
        ASSERT_TRUE(l.starts_with(head) && l.ends_with(tail)) << l;
        const std::size_t done = std::stoul(l.substr(head.size(), l.size() - head.size() - tail.size()));
        EXPECT_GT(done, last) << l;
        EXPECT_LT(done, 1000u) << l;
        last = done;
    }
}
