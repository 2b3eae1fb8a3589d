#pragma once
// A verification's counts as a dict, under the same keys whether Builder.verify checked the
// roadmap here (VerificationReport) or a daemon did (client::Verification).

#include "python_module.hpp"

namespace ispars::python {

/// `v`'s counts, with the total of what the method promises and whether it promises Invariant 1.
template <class Counts>
py::dict verification_dict(const Counts& v, std::uint64_t violations, bool invariant_promised) {
  py::dict out;
  out["violations"] = violations;
  out["invalid_vertices"] = v.invalid_vertices;
  out["invalid_edges"] = v.invalid_edges;
  out["wrong_costs"] = v.wrong_costs;
  out["sparse_not_dense"] = v.sparse_not_dense;
  out["invariant_violations"] = v.invariant_violations;
  out["invariant_vertices"] = v.invariant_vertices;
  out["invariant_promised"] = invariant_promised;
  return out;
}

}  // namespace ispars::python
