// A sliding window of canvas rows holding every layer that crosses them, as patches on the canvas grid.
#pragma once

#include <memory>
#include <vector>

#include "blend/layer_rows.h"
#include "blend/seam_grid.h"

namespace gdp::blending {

// Rows [top, bottom) of the canvas, each layer crossing them as a Patch (canvas columns, absolute
// rows). Layers are opened when the window reaches their first row and closed after their last;
// memory: the window's rows times the widths of the layers crossing them.
class LayerWindow {
 public:
  explicit LayerWindow(const BlendPlan& plan);
  ~LayerWindow();
  // Moves the window to [top, bottom): both only grow. Rows are read once each.
  void slide(int top, int bottom);
  int top() const { return top_; }
  int bottom() const { return bottom_; }
  // Patch of layer k (null when k crosses none of the window's rows).
  const std::vector<const Patch*>& layers() const { return by_layer_; }

 private:
  struct Open;
  void read_row(int y);
  const BlendPlan& plan_;
  int top_ = 0, bottom_ = 0;
  std::vector<Footprint> where_;
  std::vector<int> by_top_;
  std::size_t next_ = 0;
  std::vector<std::unique_ptr<Open>> open_;
  std::vector<const Patch*> by_layer_;
};

}  // namespace gdp::blending
