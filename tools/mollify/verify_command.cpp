// `mollify verify` (verify_command.hpp): the front end. The arguments come
// from mollify::verify::samples (a library) or the CSV rows; the values from
// the child process or the CSV; compare() judges. Nothing is printed before
// every value is in, so a failure leaves no half report.
#include "verify_command.hpp"

#include "foreign_function.hpp"
#include "output.hpp"
#include "samples_csv.hpp"

#include <mollify/error.hpp>
#include <mollify/verify.hpp>

#include <charconv>
#include <chrono>
#include <cmath>
#include <iostream>

namespace mollify::app {

namespace {

constexpr int within_bound = 0;
constexpr int outside_bound = 1;
constexpr int bad_input = 2;

std::string shortest(double x) {
    char buf[32];
    return std::string(buf, std::to_chars(buf, buf + sizeof buf, x).ptr);
}

verify::Options core_options(const VerifyOptions& o) {
    verify::Options v;
    v.convention = o.convention;
    v.ulps = o.ulps;
    v.seed = o.seed;
    v.uniform = o.points;
    return v;
}

void check(const VerifyOptions& o) {
    if (!(o.ulps >= 0) || !std::isfinite(o.ulps)) fail("--ulps " + shortest(o.ulps) + ": a bound >= 0 is needed");
    if (!(o.timeout > 0) || !std::isfinite(o.timeout) || o.timeout > 86400)
        fail("--timeout " + shortest(o.timeout) + ": seconds in (0, 86400] are needed");
    const int sources = !o.library.empty() + !o.samples.empty() + !o.arguments.empty();
    if (sources != 1) fail("give exactly one of --library (with --symbol), --samples FILE.csv, --write-arguments FILE.csv");
    if (!o.library.empty() && o.symbol.empty()) fail("--library needs --symbol, the function's name");
    if (o.library.empty() && !o.symbol.empty()) fail("--symbol needs --library");
}

// The values of `symbol` at the samples, from the child process.
std::vector<double> evaluate(const VerifyOptions& o, const std::vector<verify::Sample>& samples) {
    std::vector<double> r(samples.size()), h(samples.size());
    for (std::size_t i = 0; i < samples.size(); ++i) {
        r[i] = samples[i].r;
        h[i] = samples[i].h;
    }
    const auto timeout = std::chrono::milliseconds(static_cast<long long>(std::ceil(o.timeout * 1000)));
    return evaluate_foreign({o.library, o.symbol}, r, h, timeout);
}

// The arguments as CSV (header r,h,value; value left to the other language).
std::string arguments_csv(const std::vector<verify::Sample>& samples) {
    std::string text = "r,h\n";
    for (const auto& s : samples) text += shortest(s.r) + "," + shortest(s.h) + "\n";
    return text;
}

void print(const verify::Report& report, const std::string& source) {
    const std::string table = report.to_string();
    std::cout << table;
    if (!table.empty() && table.back() != '\n') std::cout << "\n";
    const std::string hard = std::to_string(report.hard_points_compared) + " of " + std::to_string(report.hard_points);
    if (!report.complete()) std::cout << "  (mollify verify --write-arguments writes every hard point)\n";
    std::cout << "verdict: " << source << (report.passed() ? " PASSES" : " FAILS") << ": max " << shortest(report.max_ulps)
              << (report.float_ulps ? " float" : "") << " ulps " << (report.passed() ? "<=" : ">") << " "
              << shortest(report.bound) << " over " << report.points << " points";
    if (report.passed() && !report.complete()) std::cout << ", the given rows only (" << hard << " hard points)";
    if (report.diagnosis) std::cout << " (" << report.diagnosis->text << ")";  // the table names its kind
    std::cout << "\n";
}

int run(const VerifyOptions& o) {
    check(o);
    const verify::Quantity quantity = verify::parse_quantity(o.quantity);
    const verify::Options options = core_options(o);
    if (!o.arguments.empty()) {
        const auto samples = verify::samples(o.spec, o.dim, quantity, options);
        write_atomically(o.arguments, arguments_csv(samples));
        std::cout << "mollify verify: wrote " << samples.size() << " arguments (r, h) to " << o.arguments
                  << "; add a value column and run mollify verify " << o.spec << " --dim " << o.dim
                  << " --samples FILE.csv\n";
        return within_bound;
    }
    std::vector<verify::Sample> samples;
    std::vector<double> values;
    std::string source;
    if (!o.library.empty()) {
        samples = verify::samples(o.spec, o.dim, quantity, options);  // bad spec/convention before any child
        values = evaluate(o, samples);
        source = o.symbol + " (" + o.library + ")";
    } else {
        const SampleTable table = read_samples_csv(o.samples);
        samples.resize(table.r.size());
        for (std::size_t i = 0; i < samples.size(); ++i) samples[i] = {table.r[i], table.h[i]};
        values = table.value;
        source = o.samples;
    }
    const verify::Report report = verify::compare(o.spec, o.dim, quantity, samples, values, options);
    print(report, source);
    return report.passed() ? within_bound : outside_bound;
}

}  // namespace

CLI::App* add_verify_command(CLI::App& app, VerifyOptions& o) {
    auto* v = app.add_subcommand(
        "verify", "check someone's kernel against the exact one: a C-ABI function double f(double r, double h) in a "
                  "shared library (C, C++, Fortran bind(C)), or a CSV of r,h,value rows from any language; exit "
                  "status 0 within --ulps, 1 outside (with a diagnosis), 2 bad input");
    v->add_option("spec", o.spec, "kernel spec, e.g. wendland:k=2")->required();
    v->add_option("--dim", o.dim, "dimension")->required();
    v->add_option("--library", o.library, "shared library (.so) with the function, run in a child process");
    v->add_option("--symbol", o.symbol, "the function's name in the library: double SYMBOL(double r, double h)");
    v->add_option("--samples", o.samples, "CSV file with a header naming the columns r, h, value");
    v->add_option("--write-arguments", o.arguments,
                  "write the verification arguments (r,h) as CSV, for a code that evaluates them itself");
    v->add_option("--quantity", o.quantity, "value, dr, potential, force or grad_over_r")->capture_default_str();
    v->add_option("--convention", o.convention, "cpp, phantom, swift, gadget4, c, fortran, python")
        ->capture_default_str();
    v->add_option("--ulps", o.ulps, "the bound: largest error allowed in ulps")->capture_default_str();
    v->add_option("--seed", o.seed, "seed of the uniform points")->capture_default_str();
    v->add_option("--points", o.points, "uniform points besides the hard ones")
        ->check(CLI::Range(std::size_t{0}, verify::max_uniform_points))  // (else CLI11 wraps -5 to 2^64 - 5)
        ->capture_default_str();
    v->add_option("--timeout", o.timeout, "seconds one evaluation may take before it counts as hung")
        ->capture_default_str();
    return v;
}

int run_verify(const VerifyOptions& o) {
    try {
        return run(o);
    } catch (const std::exception& e) {  // mollify::Error: the bad input named
        std::cerr << "mollify verify: error: " << e.what() << "\n";
        return bad_input;
    }
}

}  // namespace mollify::app
