// Running any application on the sphere: PQ images solved in place, equirectangular ones
// resampled to PQ, solved there and resampled back (--sphere).
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "gdp/rows.h"
#include "gdp/sphere.h"

namespace gdp {

// Wraps an application's readers and writer. Built from the size of its main input: 4:1 is a
// PQ image (readers and writer are used as they are), 2:1 an equirectangular one (each reader
// is resampled to a PQ image of height pq_height(), the PQ output rows are resampled back to
// the input's size when the writer is committed). The solver's domain must be
// Domain::Spherical either way. The resampling holds whole images in memory today (the
// resampler is in-core; docs/sphere.md).
class SphereRows {
 public:
  // `name` names the input in errors (InputError when the size is neither 2:1 nor 4:1);
  // pq_height 0: sphere::default_pq_height for the input's pixel count.
  SphereRows(int width, int height, const std::string& name, int pq_height = 0);
  ~SphereRows();

  bool resampled() const { return resampled_; }
  int pq_height() const { return pq_height_; }
  // A PQ view of `input`, which must have the main input's size (InputError naming
  // `input_name` otherwise): the reader itself, or a resampled copy; `nearest` for label maps
  // (values copied, never blended). Valid while this lives.
  RowReader& input(RowReader& input, const std::string& input_name, bool nearest = false);
  // Where the application writes its PQ rows; committing it commits `out` (after resampling
  // back to the input's size when the input was equirectangular).
  RowWriter& output(RowWriter& out, int channels);

 private:
  int width_, height_, pq_height_;
  bool resampled_;
  std::string name_;
  std::vector<std::unique_ptr<RowReader>> readers_;
  std::unique_ptr<RowWriter> writer_;
};

}  // namespace gdp
