// SPDX-License-Identifier: MIT
// The collision operators a scene can name (`[lattice] collision`), in the order of
// dld::kCollisionNames (shared/scene.hpp), and the compile-time dispatch from a scene's choice to
// the fused kernel's instantiation. A new operator: its file in fluid/collision/, one line here,
// one name in kCollisionNames (a static_assert checks the two lists agree).
#pragma once
#include <cstddef>
#include <string_view>
#include <tuple>

#include "fluid/collision/bgk.hpp"
#include "fluid/collision/mrt.hpp"
#include "fluid/collision/trt.hpp"
#include "shared/scene.hpp"

namespace dld::fluid {

using CollisionOperators = std::tuple<Bgk, Trt, Mrt>;

namespace detail {
template <std::size_t... K>
constexpr bool names_agree(std::index_sequence<K...>) {
  return ((std::string_view(std::tuple_element_t<K, CollisionOperators>::kName) ==
           kCollisionNames[K]) &&
          ...);
}
}  // namespace detail
static_assert(
    std::tuple_size_v<CollisionOperators> == kCollisionNames.size() &&
        detail::names_agree(std::make_index_sequence<std::tuple_size_v<CollisionOperators>>{}),
    "CollisionOperators and dld::kCollisionNames must list the same operators in order");

/// Calls `f.template operator()<Operator>()` for the operator a scene chose.
template <typename F>
decltype(auto) with_collision(CollisionKind kind, F&& f) {
  return [&]<std::size_t... K>(std::index_sequence<K...>)->decltype(auto) {
    using R = decltype(f.template operator()<std::tuple_element_t<0, CollisionOperators>>());
    R out{};
    ((static_cast<std::size_t>(kind) == K
          ? void(out = f.template operator()<std::tuple_element_t<K, CollisionOperators>>())
          : void()),
     ...);
    return out;
  }
  (std::make_index_sequence<std::tuple_size_v<CollisionOperators>>{});
}

/// The rates function of the operator a scene chose (for the relaxation field).
inline RelaxationRates (*rates_function(CollisionKind kind))(double, double) {
  return with_collision(kind, []<typename C>() { return &C::rates; });
}

}  // namespace dld::fluid
