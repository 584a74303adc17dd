// Row kernels (the input pass's guidance differences, right-hand sides and starting guesses; dot products), for x86-64-v3 and the baseline with the same bits.
#pragma once

#include <cstddef>

namespace gdp::multigrid {

// out[i] = beta * (to[i] - from[i]), the difference taken in double, where keep[i] is set and the
// difference is finite, else +0; i in [0, n).
void kept_differences(const float* from, const float* to, const unsigned char* keep, double beta, double* out, int n);

// out[i] = T(scale * v[i] + add[i]), or T(scale * v[i] + 0.0) where add is null; i in [0, n).
template <class T>
void scaled_rhs(const double* v, const double* add, double scale, T* out, int n);

// The starting guess and the weights of a row of `channels` planes `stride` apart (pointers at the
// first column): u = in where finite, else +0; w[i] = 1 where counted[i] is set and every channel
// of in is finite, else +0; i in [0, n).
template <class T>
void guess_and_weights(const float* in, std::size_t stride, int channels, const unsigned char* counted, T* u, T* w,
                       int n);

// <w, u> over one row, accumulated in double in column order, eight partial sums (every schedule
// uses this: the same bits everywhere).
template <class T>
double row_dot(const T* w, const T* u, int n);
// |r|^2 over one row: row_dot(r, r, n)'s bits, in about 2/3 of its time.
template <class T>
double row_squares(const T* r, int n);

}  // namespace gdp::multigrid
