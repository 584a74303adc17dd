// StripFilesReader: one image from several files side by side, each decoded only where needed.
#include "gdp/strip_files.h"

#include <algorithm>
#include <filesystem>

#include <fmt/format.h>

#include "gdp/errors.h"

namespace gdp {

std::string with_rank(std::string pattern, int rank) {
  const std::string number = std::to_string(rank);
  for (auto at = pattern.find(kRankKey); at != std::string::npos; at = pattern.find(kRankKey, at + number.size()))
    pattern.replace(at, kRankKey.size(), number);
  return pattern;
}

StripFilesReader::StripFilesReader(const std::string& path) {
  if (path.find(kRankKey) == std::string::npos) {
    strips_.push_back(Strip{path, 0, 0, 0, 0, std::make_unique<ImageFileReader>(path)});
  } else {
    for (int i = 0;; ++i) {
      const std::string p = with_rank(path, i);
      std::error_code ec;
      if (!std::filesystem::exists(p, ec)) {
        if (i == 0) throw InputError(fmt::format("{}: no strip {} (strips are numbered from 0)", path, p));
        break;
      }
      strips_.push_back(Strip{p, 0, 0, 0, 0, std::make_unique<ImageFileReader>(p)});
    }
  }
  const ImageFileReader& first = *strips_.front().reader;
  info_ = first.info();
  height_ = first.height();
  channels_ = first.channels();
  for (Strip& s : strips_) {
    if (s.reader->height() != height_ || s.reader->channels() != channels_)
      throw InputError(fmt::format("{}: {}x{} with {} channel(s), but {} has height {} and {} channel(s)", s.path,
                                   s.reader->width(), s.reader->height(), s.reader->channels(), strips_.front().path,
                                   height_, channels_));
    s.x0 = width_;
    s.width = s.reader->width();
    s.begin = 0;
    s.end = s.width;
    width_ += s.width;
  }
}

StripFilesReader::~StripFilesReader() = default;

void StripFilesReader::set_columns(int begin, int end) {
  for (Strip& s : strips_) {
    s.begin = std::clamp(begin - s.x0, 0, s.width);
    s.end = std::clamp(end - s.x0, 0, s.width);
    if (s.begin < s.end) s.reader->set_columns(s.begin, s.end);  // others are never decoded
  }
}

void StripFilesReader::read_row(int y, std::span<float> out) {
  if (strips_.size() == 1 && strips_.front().begin < strips_.front().end)
    return strips_.front().reader->read_row(y, out);
  for (Strip& s : strips_) {
    if (s.begin >= s.end) continue;
    row_.resize(static_cast<std::size_t>(channels_) * s.width);
    s.reader->read_row(y, row_);
    for (int c = 0; c < channels_; ++c)
      std::copy(row_.begin() + static_cast<std::ptrdiff_t>(c) * s.width + s.begin,
                row_.begin() + static_cast<std::ptrdiff_t>(c) * s.width + s.end,
                out.begin() + static_cast<std::ptrdiff_t>(c) * width_ + s.x0 + s.begin);
  }
}

void StripFilesReader::read_ahead() {
  const auto decoded = [](const Strip& s) { return s.begin < s.end; };
  const auto n = static_cast<std::size_t>(std::count_if(strips_.begin(), strips_.end(), decoded));
  for (Strip& s : strips_)  // the strips share one file's bytes ahead
    if (decoded(s)) s.reader->read_ahead(ImageFileReader::kAheadBytes / std::max<std::size_t>(n, 1));
}

void StripFilesReader::rewind() {
  for (Strip& s : strips_)
    if (s.begin < s.end) s.reader->rewind();
}

}  // namespace gdp
