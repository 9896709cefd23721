// A kernel chosen by its spec at run time (no table header, any kernel the
// grammar names). Prints W(1/2) of the kernel named on the command line
// (default wendland:k=2) in 3D, h = 1, to 17 significant digits.
#include <mollify/kernel.hpp>

#include <cstdio>
#include <exception>

int main(int argc, char** argv) {
    try {
        const mollify::Kernel w = mollify::kernel(argc > 1 ? argv[1] : "wendland:k=2", 3);
        std::printf("%.17g\n", w.value(0.5, 1.0));
    } catch (const mollify::Error& e) {
        std::fprintf(stderr, "runtime_kernel: %s\n", e.what());
        return 2;
    }
}
