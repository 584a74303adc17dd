// An input image kept as vertical strips in several files side by side (per-band inputs), or in one file.
#pragma once

#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "gdp/image_io.h"
#include "gdp/image_stream.h"

namespace gdp {

// The placeholder in file names that stands for an MPI rank or a strip's number.
inline constexpr std::string_view kRankKey = "{rank}";
// `pattern` with every {rank} replaced by `rank`.
std::string with_rank(std::string pattern, int rank);

// Reads `path` as ImageFileReader does; a path with {rank} in it names the strips of one image
// instead: {rank} replaced by 0, 1, 2, ... for as long as such a file exists, placed left to
// right (`in_{rank}.tif`: in_0.tif, in_1.tif, ...). Strips may have any widths; they must share
// height and channel count (else InputError naming the strip). After set_columns() only the
// strips that overlap the columns are decoded (a rank of a distributed solve opens its own and
// its neighbours' edges, whatever the number of ranks). info() is the first strip's.
class StripFilesReader final : public RowReader {
 public:
  explicit StripFilesReader(const std::string& path);
  ~StripFilesReader() override;
  const ImageFileInfo& info() const { return info_; }
  int strips() const { return static_cast<int>(strips_.size()); }
  int width() const override { return width_; }
  int height() const override { return height_; }
  int channels() const override { return channels_; }
  void read_row(int y, std::span<float> out) override;
  void rewind() override;
  void read_ahead();  // ImageFileReader::read_ahead() of every strip decoded
  void set_columns(int begin, int end) override;

 private:
  struct Strip {
    std::string path;
    int x0 = 0, width = 0;
    int begin = 0, end = 0;  // the columns wanted, in the strip's own coordinates
    std::unique_ptr<ImageFileReader> reader;  // opened, decoding only if read (begin < end)
  };
  std::vector<Strip> strips_;
  ImageFileInfo info_;
  int width_ = 0, height_ = 0, channels_ = 0;
  std::vector<float> row_;
};

}  // namespace gdp
