// SPDX-License-Identifier: MIT
// The study's five initial states at its lattice (dx = 0.4 um, 2000-face cells): overlap-free,
// haematocrit within 1 percentage point (label "long": minutes).
#include <gtest/gtest.h>

#include "packing_states.hpp"

namespace dld::membrane {
namespace {

class StudyStatesFine : public ::testing::TestWithParam<test::StudyState> {};

TEST_P(StudyStatesFine, AreClearOfTheContactRangeAndGiveTheStudysHaematocrit) {
  test::check_study_state(std::string(DLD_SOURCE_DIR) + "/configs/membrane/packing_dld.toml",
                          GetParam());
}

INSTANTIATE_TEST_SUITE_P(Study, StudyStatesFine, ::testing::ValuesIn(test::kStudyStates),
                         [](const auto& param_info) {
                           return std::to_string(param_info.param.cells) + "cells";
                         });

}  // namespace
}  // namespace dld::membrane
