// Fattal's multi-scale attenuation over the pyramid's coarse levels, coarsest first, level by level.
#pragma once

#include <memory>

#include "apps/tonemap_pyramid.h"

namespace gdp::apps::tonemap {

// Phi_k = phi_k * expand(Phi_{k+1}) for k = levels-1 down to 1 (Phi of the coarsest level is its
// own phi), with phi_k from |grad H_k| and a_k = alpha * mean |grad H_k|; levels finer than
// `first` have phi_k = 1. Each level is one pass over its store; the stores of H_k and
// Phi_{k+1} are released as soon as Phi_k is done. Returns Phi_1 (rows of level 1), or null
// when the pyramid has a single level.
std::unique_ptr<schedule::RowStore<float>> coarse_attenuation(Pyramid& pyramid, Domain domain, double alpha,
                                                              double beta, int first,
                                                              const schedule::StorePolicy& policy);

}  // namespace gdp::apps::tonemap
