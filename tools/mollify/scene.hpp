// A scene file (TOML, scenes/*.toml): which experiment, which kernels, which
// parameters, where the output goes. Parsed with toml++; every error names
// the file, the key and (where toml++ knows it) the line, and is a
// mollify::Error. Keys are dotted paths into the file ("franz.epsilon").
//
//   [scene]
//   name = "franz-torus"          # also the default output folder out/NAME
//   experiment = "franz"          # one of experiments() (experiment.hpp)
//   title = "Franz §6.2.2 ..."
//   description = "..."           # optional; no other keys allowed in [scene]
//   [franz]                       # the experiment's own section
//   epsilon = [0.25, 0.2]
#pragma once

#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace mollify::app {

class Scene {
public:
    // Reads and parses a scene file; a missing file, a TOML syntax error, a
    // missing [scene] name/experiment, a name that is not a plain folder name
    // or an unknown key in [scene] is an Error naming the file (and line).
    // (Whether scene.experiment exists is checked by find_experiment().)
    static Scene load(const std::filesystem::path& file);
    // Parses scene text (tests, embedded default scenes); origin names it in errors.
    static Scene parse(std::string_view text, std::string origin);

    Scene(Scene&&) noexcept;
    Scene& operator=(Scene&&) noexcept;
    ~Scene();

    const std::string& origin() const;  // the file name, for messages
    const std::string& text() const;    // the scene's TOML text (copied into the output folder)
    std::string name() const;           // scene.name
    std::string experiment() const;     // scene.experiment
    std::string title() const;          // scene.title, or name()

    bool has(std::string_view key) const;
    // Typed getters: a missing key (without fallback) or a value of another
    // type is an Error naming origin, key and line. Integers convert to double.
    double number(std::string_view key) const;
    double number(std::string_view key, double fallback) const;
    long integer(std::string_view key) const;
    long integer(std::string_view key, long fallback) const;
    std::string string(std::string_view key) const;
    std::string string(std::string_view key, std::string_view fallback) const;
    bool boolean(std::string_view key, bool fallback) const;
    std::vector<double> numbers(std::string_view key) const;  // array of numbers
    std::vector<long> integers(std::string_view key) const;
    std::vector<std::string> strings(std::string_view key) const;

    // Checks a number: an Error "ORIGIN: KEY = VALUE: WHY" unless ok.
    double positive(std::string_view key) const;  // number(key) > 0 and finite
    // An Error naming origin and key with the given reason (for checks the
    // experiment makes itself, e.g. "epsilon too small for the spacing").
    [[noreturn]] void reject(std::string_view key, const std::string& why) const;

    // Keys present in [section] that are not in `known`: an Error naming
    // them (a misspelt key must not be silently ignored).
    void only(std::string_view section, const std::vector<std::string_view>& known) const;

private:
    struct Impl;
    explicit Scene(std::unique_ptr<Impl>);
    std::unique_ptr<Impl> impl_;
};

}  // namespace mollify::app
