// mollify-gen: the exact generator's command line (README, "Command line").
// Bad arguments: a message naming the bad value, exit status 2, nothing written.
#include "catalogue.hpp"
#include "certificate.hpp"
#include "conventions.hpp"
#include "data_dir.hpp"
#include "emit.hpp"
#include "errata.hpp"
#include "errata_codes.hpp"
#include "error.hpp"
#include "query.hpp"
#include "rounding.hpp"
#include "search_choices.hpp"
#include "softening.hpp"
#include "softening_certificate.hpp"
#include "target.hpp"
#include "vandermonde.hpp"

#include <CLI/CLI.hpp>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iostream>

using namespace mollify::gen;

namespace {

constexpr int bad_input = 2;

std::vector<Spec> parse_specs(const std::vector<std::string>& texts) {
    std::vector<Spec> specs;
    for (const auto& t : texts) specs.push_back(parse_spec(t));
    return specs;
}

int run_emit(const std::string& out, const std::vector<std::string>& only, const std::string& format,
             const std::string& target_name, const std::vector<int>& only_dims, bool allow_negative_lobes,
             const std::string& choices_file) {
    if (format != "cpp" && format != "data") fail("--format " + format + " is neither cpp nor data");
    if (target_name != "cpp") {
        target(target_name);  // Error naming an unknown one
        if (format != "cpp") fail("--format " + format + " is for --target cpp only (not " + target_name + ")");
    }
    if (allow_negative_lobes && target_name != "swift")
        fail("--allow-negative-lobes is for --target swift (whose kernel_deval clamps the sign), not " + target_name);
    for (int d : only_dims)
        if (d < 1 || d > 3) fail("--dim " + std::to_string(d) + " is outside 1..3");
    std::string command = "mollify-gen emit" + (target_name == "cpp" ? std::string() : " --target " + target_name) +
                          (format == "cpp" ? std::string() : " --format " + format) +
                          (allow_negative_lobes ? " --allow-negative-lobes" : "");
    std::vector<Spec> specs = only.empty() ? default_specs() : parse_specs(only);
    for (const Spec& s : specs) command += only.empty() ? "" : " --only " + spec_string(s);
    for (int d : only_dims) command += " --dim " + std::to_string(d);
    std::vector<CatalogueEntry> entries = expand_dimensions(specs);
    if (!choices_file.empty()) search_afresh();
    if (!only_dims.empty())  // --dim: only these dimensions
        std::erase_if(entries, [&](const CatalogueEntry& e) {
            return std::find(only_dims.begin(), only_dims.end(), e.dim) == only_dims.end();
        });
    if (target_name != "cpp") {  // the dimensions the target takes (Phantom: 3D)
        const std::vector<int>& dims = convention(target_name).dims;
        std::erase_if(entries, [&](const CatalogueEntry& e) { return std::find(dims.begin(), dims.end(), e.dim) == dims.end(); });
    }
    // A kernel asked for by --only that none of the dimensions left takes is
    // an error naming it (viscosity with --dim 1 had written no kernel, exit 0).
    for (const Spec& s : only.empty() ? std::vector<Spec>{} : specs)
        if (std::none_of(entries.begin(), entries.end(), [&](const CatalogueEntry& e) { return spec_string(e.spec) == spec_string(s); })) {
            std::string has;
            for (const CatalogueEntry& e : expand_dimensions({s})) has += (has.empty() ? "" : ", ") + std::to_string(e.dim);
            std::string asked, taken;
            for (int d : only_dims) asked += (asked.empty() ? "" : ", ") + std::to_string(d);
            if (target_name != "cpp")
                for (int d : convention(target_name).dims) taken += (taken.empty() ? "" : ", ") + std::to_string(d);
            fail("--only " + spec_string(s) + " exists in D = " + has + ", but " +
                 (asked.empty() ? "" : "--dim asks for D = " + asked + (taken.empty() ? "" : " and ")) +
                 (taken.empty() ? "" : "--target " + target_name + " takes D = " + taken) + ": nothing to emit");
        }
    // Each kernel's file is staged (written beside its place) as soon as it
    // is rendered, while the other kernels are still being computed; all
    // are renamed into place at the end, or none.
    StagedFiles files(out);
    const EmitResult r = target_name == "cpp"
                             ? render_catalogue(entries, command, format == "cpp" ? EmitFormat::cpp : EmitFormat::data,
                                                [&](const std::string& path, const std::string& text) { files.stage(path, text); })
                             : render_target(entries, command, target_name, allow_negative_lobes);
    if (!r.failed_certificates.empty()) {
        for (const auto& f : r.failed_certificates) std::cerr << "certificate failed: " << f << "\n";
        std::cerr << r.failed_certificates.size() << " certificates failed; nothing written\n";
        return 1;
    }
    const std::size_t written = files.commit(r);
    if (!choices_file.empty()) {
        std::ofstream file(choices_file, std::ios::binary);
        file << search_choices_file();
        file.close();
        if (!file) fail("--search-choices: cannot write " + choices_file);
    }
    std::cout << "wrote " << written << " of " << r.files.size() << " files to " << out << " (the others unchanged): "
              << r.kernels << " kernels, "
              << r.certificates << " certificates, all exact\n";
    return 0;
}

int run_value(const std::string& spec_text, int dim, const std::string& r_text, const std::string& name, int digits,
              bool exact) {
    const Q r = parse_rational_or_hex_float(r_text, "--r");
    if (r < 0) fail("--r " + r_text + " must be >= 0 (a radial distance)");
    if (digits < 1 || digits > max_decimal_digits)
        fail("--digits " + std::to_string(digits) + " is outside 1.." + std::to_string(max_decimal_digits));
    const ExactKernel k = make_kernel(parse_spec(spec_text), dim);
    const std::string where = name + " of " + spec_string(k.spec) + " in D = " + std::to_string(dim);
    const ExactValue v = exact_value(query(k, name), r, Q(1), Scaling{}, where);
    std::cout << (v.exact ? decimal(*v.exact, digits) : decimal(v.evaluate, digits)) << "\n";
    if (exact) std::cout << v.closed_form << "\n";
    return 0;
}

int run_weights(const std::vector<std::string>& radii_text) {
    std::vector<Q> radii;
    for (const auto& t : radii_text) radii.push_back(parse_rational(t, "--radii"));
    for (const Q& w : vandermonde_weights(radii)) std::cout << pq(w) << "\n";
    return 0;
}

// The published codes' constants (transcriptions/codes/): every entry,
// right ones included, then the counts.
int run_code_errata(const std::string& dir) {
    const CodeErrataReport report = check_code_errata(std::filesystem::path(dir) / "codes");
    for (const auto& v : report.verdicts) std::cout << format_line(v) << "\n";
    std::cout << "checked " << report.verdicts.size() << " published constants of codes, " << report.wrong()
              << " wrong\n";
    return 0;
}

int run_errata(const std::string& dir, bool codes) {
    if (codes) return run_code_errata(dir);
    const ErrataReport report = check_errata(dir);
    for (const auto& d : report.discrepancies) std::cout << format_line(d) << "\n";
    std::cout << "checked " << report.checked << " entries, " << report.discrepancies.size() << " discrepancies\n";
    return 0;
}

// The softening derivatives' certificates, then what the joins above the
// guaranteed order do (continuous, a jump, or infinite), stated.
int print_softening(const ExactKernel& k) {
    const std::string name = spec_string(k.spec) + " D=" + std::to_string(k.dim);
    const std::vector<Radial> derivatives = softening_derivatives(k);
    const SofteningSmoothness s = softening_smoothness(k, derivatives);
    int failed = 0;
    for (const Certificate& c : softening_certificates(s)) {
        std::cout << (c.passed ? "ok    " : "FAIL  ") << name << "  " << c.what << "  [" << c.detail << "]\n";
        failed += !c.passed;
    }
    for (const Join& j : s.joins) {
        if (j.order <= s.guaranteed) continue;
        std::cout << "note  " << name << "  " << join_name(j) << ": ";
        if (j.continuous()) std::cout << "continuous (above the guaranteed order " << s.guaranteed << ")\n";
        else if (!j.left || !j.right) std::cout << "infinite one-sided limit\n";
        else std::cout << "jumps by " << (*j.right - *j.left).to_string() << "\n";
    }
    std::cout << "smooth " << name << "  phi is C^" << s.guaranteed << " by the kernel's smoothness; phi^(0.."
              << s.continuous_at_edge << ") continuous with the Green's function at the edge; phi^(0.."
              << finite_at_origin(derivatives) << ") finite at r = 0";
    if (k.dim == 3) std::cout << "; D_soft_1.." << finite_at_origin(swift_d_soft(k)) + 1 << " finite at u = 0";
    std::cout << "\n";
    return failed;
}

int run_certify(const std::vector<std::string>& specs, const std::vector<int>& dims, bool softening) {
    int failed = 0;
    for (const Spec& s : parse_specs(specs))
        for (int dim : dims) {
            const ExactKernel k = make_kernel(s, dim);
            if (softening) {
                failed += print_softening(k);
                continue;
            }
            for (const Certificate& c : certify(k, derive_quantities(k))) {
                std::cout << (c.passed ? "ok    " : "FAIL  ") << spec_string(s) << " D=" << dim << "  " << c.what
                          << "  [" << c.detail << "]\n";
                failed += !c.passed;
            }
        }
    return failed ? 1 : 0;
}

}  // namespace

int main(int argc, char** argv) {
    CLI::App app{"mollify-gen: exact smoothing kernels, potentials and weights, and the tables the runtime uses"};
    app.set_version_flag("--version", std::string("mollify-gen ") + MOLLIFY_GENERATOR_VERSION);
    app.require_subcommand(1);

    auto* emit = app.add_subcommand("emit", "write the constexpr tables and catalogue.json");
    std::string out = "generated";
    std::vector<std::string> only;
    emit->add_option("--out", out, "output folder")->capture_default_str();
    emit->add_option("--only", only, "emit only these kernel specs (all dimensions)");
    std::string format = "cpp";
    emit->add_option("--format", format, "cpp: C++ headers and catalogue.json; data: table files (write_data.cpp)")
        ->capture_default_str();
    std::string target_name = "cpp";
    emit->add_option("--target", target_name,
                     "cpp: mollify's tables; c, fortran, python: kernel files in mollify's convention; phantom, swift, "
                     "gadget4: drop-in kernel files for those codes (target.hpp)")
        ->capture_default_str();
    std::vector<int> emit_dims;
    emit->add_option("--dim", emit_dims, "only these dimensions (1..3; default: every one the kernel and target have)");
    std::string choices_file;
    emit->add_option("--search-choices", choices_file,
                     "search every piece's form afresh (not from the compiled-in choices, search_choices.hpp) and write "
                     "the choices to this file (generator/search_choices.def for the default catalogue)");
    bool allow_negative_lobes = false;
    emit->add_flag("--allow-negative-lobes", allow_negative_lobes,
                   "--target swift: write kernels not proved W >= 0, W' <= 0 without SWIFT's sign clamps");

    auto* value = app.add_subcommand("value", "one exact value, correctly rounded to --digits significant digits");
    std::string spec_text, r_text, name = "value";
    int dim = 3, digits = 40;
    bool exact = false;
    value->add_option("spec", spec_text, "kernel spec, e.g. wendland:k=2,l=1")->required();
    value->add_option("--dim", dim, "dimension 1..3")->required();
    value->add_option("--r", r_text, "radius r/h: p/q, a decimal, or a hex-float (a double exactly)")->required();
    value->add_option("--quantity", name, query_names())->capture_default_str();
    value->add_option("--digits", digits, "significant digits")->capture_default_str();
    value->add_flag("--exact", exact, "also print the exact closed form");

    auto* weights = app.add_subcommand("weights", "exact weights of the combination with these radii (Franz Prop. 4.24)");
    std::vector<std::string> radii;
    weights->add_option("--radii", radii, "distinct positive radii, e.g. 1/3,2/3,1")->required()->delimiter(',');

    auto* errata = app.add_subcommand("errata", "compare the transcribed seed tables with the exact values");
    std::string transcriptions = mollify::data_dir("transcriptions", MOLLIFY_TRANSCRIPTIONS_DIR);
    errata->add_option("--transcriptions", transcriptions, "folder of transcribed tables")->capture_default_str();
    bool errata_codes = false;
    errata->add_flag("--codes", errata_codes,
                     "the published constants of SPH and N-body codes (DIR/codes/*.json) instead of the seed documents");

    auto* certify_cmd = app.add_subcommand("certify", "print the exact certificates of kernels");
    std::vector<std::string> certify_specs;
    std::vector<int> certify_dims = {1, 2, 3};
    certify_cmd->add_option("specs", certify_specs, "kernel specs")->required();
    certify_cmd->add_option("--dim", certify_dims, "dimensions")->delimiter(',');
    bool certify_softening = false;
    certify_cmd->add_flag("--softening", certify_softening,
                          "the softening derivatives phi^(0..6): continuity across breakpoints and with the Green's "
                          "function at the edge");

    if (argc > 1 && argv[1][0] != '-') {
        const std::string command = argv[1];
        bool known = false;
        for (const auto* sub : app.get_subcommands({})) known = known || sub->get_name() == command;
        if (!known) {
            std::cerr << "mollify-gen: unknown command '" << command << "' (emit, value, weights, errata, certify)\n";
            return bad_input;
        }
    }
    try {
        app.parse(argc, argv);
    } catch (const CLI::CallForHelp& e) {
        return app.exit(e);
    } catch (const CLI::CallForAllHelp& e) {
        return app.exit(e);
    } catch (const CLI::CallForVersion& e) {
        return app.exit(e);
    } catch (const CLI::ParseError& e) {
        std::cerr << "mollify-gen: " << e.what() << "\n";
        return bad_input;
    }
    try {
        if (*emit) return run_emit(out, only, format, target_name, emit_dims, allow_negative_lobes, choices_file);
        if (*value) return run_value(spec_text, dim, r_text, name, digits, exact);
        if (*weights) return run_weights(radii);
        if (*errata) return run_errata(transcriptions, errata_codes);
        if (*certify_cmd) return run_certify(certify_specs, certify_dims, certify_softening);
    } catch (const Error& e) {
        std::cerr << "mollify-gen: " << e.what() << "\n";
        return bad_input;
    }
    return 0;
}
