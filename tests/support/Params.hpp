// Shared GoogleTest parameter helpers.
#pragma once

#include <core/ElementTraits.hpp>

#include <gtest/gtest.h>

#include <string>

namespace mixcon::test {

/// Test-name suffix for tests parameterized by element type.
inline std::string elementName(const ::testing::TestParamInfo<ElementType> &info) {
  return info.param == ElementType::Quad8 ? "Quad8" : "Quad4";
}

/// The two element types, for INSTANTIATE_TEST_SUITE_P.
inline auto bothElements() { return ::testing::Values(ElementType::Quad4, ElementType::Quad8); }

} // namespace mixcon::test
