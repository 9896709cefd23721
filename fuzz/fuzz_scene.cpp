// libFuzzer harness: the scene reader of `mollify run` (tools/mollify/scene.cpp,
// TOML through toml++). Any text is a Scene or a mollify::Error (never
// toml++'s own exception, never a crash), and so is every getter on it.
#include "scene.hpp"

#include <mollify/error.hpp>

#include <cstdint>
#include <string_view>

namespace {

template <class F>
void quietly(F&& f) {
    try {
        f();
    } catch (const mollify::Error&) {
    }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const std::string_view text(reinterpret_cast<const char*>(data), size);
    try {
        const auto scene = mollify::app::Scene::parse(text, "fuzz.toml");
        (void)scene.name();
        (void)scene.experiment();
        (void)scene.title();
        // The getters the experiments use, on the keys the report's scenes have.
        for (const char* key : {"franz.epsilon", "franz.kernels", "sph.n", "scene.name", "a.b.c", "vortex.dt"}) {
            quietly([&] { (void)scene.has(key); });
            quietly([&] { (void)scene.number(key); });
            quietly([&] { (void)scene.integer(key, 3); });
            quietly([&] { (void)scene.string(key, "x"); });
            quietly([&] { (void)scene.boolean(key, false); });
            quietly([&] { (void)scene.numbers(key); });
            quietly([&] { (void)scene.integers(key); });
            quietly([&] { (void)scene.strings(key); });
            quietly([&] { (void)scene.positive(key); });
        }
        quietly([&] { scene.only("franz", {"epsilon", "kernels"}); });
    } catch (const mollify::Error&) {
    }
    return 0;
}
