// The layer across a seam edge: the one label, other than a pixel's own, that its two neighbours in one direction carry.
#pragma once

namespace gdp::blending {

// The one label other than `own` (and other than `none`) among the two neighbours n1 and n2;
// `none` if neither carries one or they carry two different ones (blend's canvas and the sky's
// PQ rows both give stitching one across value per direction this way).
template <class L>
L across_label(L own, L n1, L n2, L none) {
  const bool o1 = n1 != none && n1 != own, o2 = n2 != none && n2 != own;
  if (o1 && o2) return n1 == n2 ? n1 : none;
  return o1 ? n1 : o2 ? n2 : none;
}

}  // namespace gdp::blending
