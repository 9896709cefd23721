// Part 4 of the tables runtime_forms_test compares (static_case.hpp).
#include "static_case.hpp"

#include <mollify/tables/classic/cubic_spline_D3.hpp>
#include <mollify/tables/combo/m_3_base_wendland_k_2_D1.hpp>
#include <mollify/tables/mollifier/M_1_order_6_D1.hpp>
#include <mollify/tables/mollifier/M_2_order_4_D2.hpp>
#include <mollify/tables/wendland/k_0_D1.hpp>
#include <mollify/tables/wendland/k_2_D3.hpp>
#include <mollify/tables/wendland_missing/k_2_l_1_D2.hpp>

namespace mollify::testing {

std::vector<Case> cases_4() {
    namespace tables = mollify::tables;
    return {
        case_of<tables::mollifier_M_1_order_6_D1>(),
        case_of<tables::wendland_k_0_D1>(),
        case_of<tables::mollifier_M_2_order_4_D2>(),
        case_of<tables::wendland_missing_k_2_l_1_D2>(),
        case_of<tables::wendland_k_2_D3>(),
        case_of<tables::combo_m_3_base_wendland_k_2_D1>(),
        // W and W'/r two pieces of one term each, W'/r's outer (1 - q)^2 q^-1:
        // the run-time form's fused pieces and their one-pass pair loop
        case_of<tables::cubic_spline_D3>(),
    };
}

}  // namespace mollify::testing
