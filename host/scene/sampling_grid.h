// Discrete distributions on a grid of probability steps, for the tables by which both renderers pick a texel
// of the environment map or an emissive primitive with one random number. Both renderers' random numbers are
// multiples of 2^-24 (shaders/random.h); a table whose cumulative probabilities are multiples of the same
// step picks entry i with exactly the probability it states, (cdf[i] - cdf[i - 1]), on the GPU in single
// precision as on the CPU in double, where a table of real cumulative sums picks an entry narrower than a
// step with probability 0 or one step whatever its weight. Every entry of positive weight gets at least one
// step, so none is left out, however bright its neighbours (issue 13's environment with 1e12 of dynamic
// range).
#pragma once

#include <cstdint>
#include <vector>

namespace vkrt {

// The cumulative table of `weights` in integer steps: entry i holds the steps of entries 0..i, the last
// `steps`. Each positive weight gets one step and the steps left over are shared in proportion to the
// weights, each entry's cumulative count rounded to the nearest step. Weights that sum to zero (or that are
// empty of positive entries) are shared uniformly. Throws std::length_error when there are more entries
// than steps.
std::vector<uint64_t> gridCdf(const std::vector<double>& weights, uint64_t steps);

}  // namespace vkrt
