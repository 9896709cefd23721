// mollify-gen's softening queries as a user runs them: value --quantity
// softening:n | d_soft:n | gfactor:n, certify --softening, and bad orders
// (exit status 2, a message naming the order).
#include "command.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include <unistd.h>

namespace {

using mollify::testing::Outcome;

Outcome run(const std::string& args) {
    const auto capture = std::filesystem::temp_directory_path() /
                         ("mollify-softening-cli-test-" + std::to_string(::getpid()));
    return mollify::testing::run_command(std::string(MOLLIFY_GEN) + " " + args, capture);
}

bool contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

TEST(SofteningCli, SwiftPotentialKernelAtTheOrigin) {
    // peers.md: SWIFT's Wendland C2 softening W(0) = -3, D_soft_1 = -W.
    const Outcome r = run("value wendland:k=1 --dim 3 --r 0 --quantity d_soft:1 --exact");
    ASSERT_EQ(r.status, 0) << r.err;
    EXPECT_EQ(r.out, "3.000000000000000000000000000000000000000e+00\n3\n");
}

TEST(SofteningCli, DerivativeOfThePotential) {
    // Outside the support phi = G = -1/(4 pi r): G''' = 3!/(4 pi r^4) = 3/(32 pi) at r = 2.
    const Outcome r = run("value cubic-spline --dim 3 --r 2 --quantity softening:3 --exact");
    ASSERT_EQ(r.status, 0) << r.err;
    EXPECT_TRUE(contains(r.out, "3/32 * pi^-1")) << r.out;
}

TEST(SofteningCli, BadOrdersNameTheOrder) {
    for (const auto& [quantity, message] :
         {std::pair<std::string, std::string>{"softening:7", "softening order 7 is outside 0..6"},
          {"softening:-1", "softening order -1 is outside 0..6"},
          {"d_soft:0", "D_soft order 0 is outside 1..6"},
          {"gfactor:6", "g-factor order 6 is outside 0..5"},
          {"softening:two", "order 'two' is not an integer"}}) {
        const Outcome r = run("value wendland:k=2 --dim 3 --r 1/2 --quantity " + quantity);
        EXPECT_EQ(r.status, 2) << quantity;
        EXPECT_TRUE(contains(r.err, message)) << quantity << ": " << r.err;
        EXPECT_EQ(r.out, "") << quantity;
    }
}

TEST(SofteningCli, DSoftIsThreeDimensional) {
    const Outcome r = run("value wendland:k=2 --dim 2 --r 1/2 --quantity d_soft:2");
    EXPECT_EQ(r.status, 2);
    EXPECT_TRUE(contains(r.err, "D = 2")) << r.err;
}

TEST(SofteningCli, CertifyStatesWhereTheDerivativesJump) {
    const Outcome r = run("certify --softening wendland:k=1 --dim 3");
    ASSERT_EQ(r.status, 0) << r.err;
    EXPECT_FALSE(contains(r.out, "FAIL"));
    EXPECT_TRUE(contains(r.out, "phi^(5) at r = 1 (support edge, against the Green's function) continuous")) << r.out;
    EXPECT_TRUE(contains(r.out, "phi^(6) at r = 1 (support edge, against the Green's function): jumps by")) << r.out;
    EXPECT_TRUE(contains(r.out, "D_soft_1..6 finite at u = 0")) << r.out;
}

}  // namespace
