// The multigrid kernels as operations on one row and its window of neighbouring rows.
//
// Every schedule (in-core, streaming, bands) calls these; none of them knows how rows are
// stored. rows[d + 2] points at row j + d of the same level, or is null where the level
// operator has no coupling (see LevelOperator::row_of).
#pragma once

#include <array>
#include <utility>
#include <vector>

#include "fem/axis.h"
#include "multigrid/hierarchy.h"

namespace gdp::multigrid {

template <class T>
using RowWindow = std::array<const T*, 5>;

// Temporary rows reused across calls (one per thread).
template <class T>
struct RowScratch {
  std::vector<T> a, c;           // vertical combinations with two ghost samples each side
  std::vector<T> q, k1, k2, dx;  // operator row, recurrence coefficients, corrections
  std::vector<T> inv, zero;      // reciprocal diagonal; a row of zeros for unused window rows
  std::vector<T> block_b, block_c;  // the recurrence four samples at a time (relax_row)
  std::array<std::vector<T>, 5> mirrored;  // window rows read mirrored (spherical domains)
  // The (m0, c0) pair and level that k1, k2, inv and the block terms were computed for.
  std::pair<T, T> coefficients_for{};
  const void* coefficients_op = nullptr;
  explicit RowScratch(int width = 0) { resize(width); }
  void resize(int width);
};

// Every operator kernel takes an optional per-pixel diagonal term `diag` (row j of D, or null):
// the operator is then A + D, D >= 0 being the lumped per-pixel fidelity weights (scaled like
// A by kScale; docs/weights.md). Residuals are zero where D reaches kPinnedDiagonal.

// out = (A u) on row j.
template <class T>
void apply_row(const LevelOperator<T>& op, int j, const RowWindow<T>& rows, T* out, RowScratch<T>& s,
               const T* diag = nullptr);

// r = b - (A u) on row j.
template <class T>
void residual_row(const LevelOperator<T>& op, int j, const RowWindow<T>& rows, const T* b, T* r,
                  RowScratch<T>& s, const T* diag = nullptr);

// One lexicographic Gauss-Seidel sweep of row j (left to right): rows[2] is updated in place,
// using the newest values of the row itself and whatever the other rows hold.
template <class T>
void relax_row(const LevelOperator<T>& op, int j, const RowWindow<T>& rows, T* u, const T* b,
               RowScratch<T>& s, const T* diag = nullptr);

// Restriction (P^T) of fine row j onto the coarse rows it feeds: coarse0 and coarse1 are the
// rows py[j].index[0] and [1] (possibly the same row, the second fed mirrored where py[j].mirror
// says so); tmp has the coarse width.
template <class T>
void restrict_row(const fem::Prolongation& px, const fem::ProlongationRow& pyj, const T* fine,
                  T* coarse0, T* coarse1, T* tmp);

// Prolongation (P) added into fine row j from the coarse rows py[j].index[0] and [1].
template <class T>
void prolong_row(const fem::Prolongation& px, const fem::ProlongationRow& pyj, const T* coarse0,
                 const T* coarse1, T* fine, T* tmp);

}  // namespace gdp::multigrid
