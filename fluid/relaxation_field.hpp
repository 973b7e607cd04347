// SPDX-License-Identifier: MIT
// Per-node relaxation (the viscosity contrast of SPEC section 3): each node's relaxation time and
// the two collision rates it gives, kept together. The kernel reads the rates, so a step divides
// nothing per node (1/tau and TRT's omega- are three divisions a node, a third of the coupled
// lattice step); the rates are computed where a node's tau is set, with the same formula, so the
// results are those of computing them in the kernel. Lattice units.
#pragma once
#include <cstddef>
#include <vector>

#include "fluid/collision.hpp"
#include "fluid/huge_page_allocator.hpp"

namespace dld::fluid {

class RelaxationField {
 public:
  using RatesOf = RelaxationRates (*)(double tau, double magic);
  /// `nodes` padded nodes, all at `tau`; `rates` is the collision's (Bgk::rates or Trt::rates,
  /// same Rates layout) with its magic parameter.
  RelaxationField(std::size_t nodes, double tau, RatesOf rates, double magic, bool huge_pages)
      : rates_(rates),
        magic_(magic),
        tau_(nodes, tau, HugePageAllocator<double>(huge_pages)),
        plus_(nodes, 0.0, HugePageAllocator<double>(huge_pages)),
        minus_(nodes, 0.0, HugePageAllocator<double>(huge_pages)) {
    const RelaxationRates r = rates_of(tau);
    for (std::size_t n = 0; n < nodes; ++n) plus_[n] = r.plus, minus_[n] = r.minus;
  }

  /// A relaxation time with its rates, for setting many nodes (from several threads at once).
  struct Value {
    double tau;
    RelaxationRates rates;
  };
  Value value_of(double tau) { return {tau, rates_of(tau)}; }
  void set(std::size_t node, const Value& v) {
    tau_[node] = v.tau;
    plus_[node] = v.rates.plus;
    minus_[node] = v.rates.minus;
  }
  void set(std::size_t node, double tau) { set(node, value_of(tau)); }
  double tau(std::size_t node) const { return tau_[node]; }
  std::size_t size() const { return tau_.size(); }
  const double* plus() const { return plus_.data(); }
  const double* minus() const { return minus_.data(); }

 private:
  /// The rates of tau; a field holds few distinct values (tau inside and outside the cells), so
  /// the last two are remembered rather than divided again.
  RelaxationRates rates_of(double tau) {
    for (Cached& c : cache_)
      if (c.valid && c.tau == tau) return c.rates;
    Cached& c = cache_[next_];
    next_ = 1 - next_;
    c = {true, tau, rates_(tau, magic_)};
    return c.rates;
  }
  struct Cached {
    bool valid = false;
    double tau = 0.0;
    RelaxationRates rates{};
  };
  RatesOf rates_;
  double magic_;
  Cached cache_[2];
  int next_ = 0;
  std::vector<double, HugePageAllocator<double>> tau_, plus_, minus_;
};

}  // namespace dld::fluid
