#pragma once
// The roadmap's parameters, each declared once (params/spec.hpp): the ones a scene file gives
// and a build may override, the build's own, and the bound on samples per request. Scene files,
// recipes, requests, flags and the wire all read these declarations.

#include <cstdint>
#include <limits>

#include "ispars/params/spec.hpp"

namespace ispars {

inline constexpr params::Spec<double> kDenseDelta{
    "dense_delta", 0.0, 1e6, "delta, the dense roadmap's connection radius in metres", params::Lower::open};
inline constexpr params::Spec<double> kSparseDelta{
    "sparse_delta", 0.0, 1e6, "Delta, the sparse roadmap's visibility radius in metres", params::Lower::open};
inline constexpr params::Spec<double> kStretch{"stretch", 1.0, 100.0, "t, the spanner's stretch factor"};
inline constexpr params::Spec<double> kStretchSlack{
    "stretch_slack", 0.0, 1.0,
    "the stretch rules' additive slack, a fraction of Delta: bounds t d + slack Delta (default 0; 0.5 keeps a "
    "long extend's cost per sample nearly flat, docs/results/ispars2.md)"};
inline constexpr params::Spec<std::uint64_t> kStretchSlackAfter{
    "stretch_slack_after", 0, 1'000'000'000'000,
    "the sample from which stretch_slack applies (default 0: from the first; the samples before it grow the "
    "roadmap no slack grows)"};
inline constexpr params::Spec<double> kPAccept{
    "p_accept", 0.0, 1.0, "IRIS-C: probability of admitting a state that adds no POI (default 0.2)"};

/// The samples one build or extend request may ask for, whoever sends it. Its upper bound is
/// 2^53, so that a count survives every JSON reader's double; a daemon's `max_samples` setting
/// (default 50,000,000) may lower it.
inline constexpr params::Spec<std::uint64_t> kSamples{"samples", 1, std::uint64_t{1} << 53, "samples to draw"};
/// The seed of a build's sample stream.
inline constexpr params::Spec<std::uint64_t> kSeed{"seed", 0, std::numeric_limits<std::uint64_t>::max(),
                                                   "seed of the sample stream"};

/// The seconds one tour may search, whoever asks: the daemon's TOUR, Client.tour and the offline
/// ispars.tour take the same range.
inline constexpr params::Spec<double> kTourBudget{"budget", 0.0, 3600.0, "seconds of tour search", params::Lower::open};

}  // namespace ispars
