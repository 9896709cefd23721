#include "target.hpp"

#include "error.hpp"

namespace mollify::gen {

namespace {

const std::vector<Target>& targets() {
    static const std::vector<Target> all = {
        {"c", write_c},
        {"fortran", write_fortran},
        {"python", write_python},
        {"phantom", write_phantom},
        {"swift", write_swift},
        {"gadget4", write_gadget4},
    };
    return all;
}

}  // namespace

const Target& target(const std::string& name) {
    std::string known = "cpp";
    for (const Target& t : targets()) {
        if (t.name == name) return t;
        known += ", " + t.name;
    }
    fail("--target " + name + " is not a target (" + known + ")");
}

}  // namespace mollify::gen
