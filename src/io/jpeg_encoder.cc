// Encoding JPEG with libjpeg: gray (1-2 channels given) or RGB (3-4 given), at a quality, streamed through a checked file.
#include <cstdio>
// jpeglib.h needs FILE and size_t declared first.
#include <jpeglib.h>

#include <algorithm>
#include <cstdlib>
#include <memory>
#include <vector>

#include "io/codecs.h"
#include "io/guarded_call.h"
#include "io/jpeg_errors.h"
#include "io/output_file.h"

namespace gdp::io {
namespace {

constexpr std::size_t kChunk = std::size_t{1} << 16;  // compressed bytes handed to the file at a time

// The encoder's libjpeg state (errors: io/jpeg_errors.h). Compressed bytes go to an
// io::OutputFile, so a full disk is a recorded failure, never libjpeg's exit().
struct JpegWriteState : JpegErrors {
  jpeg_compress_struct cinfo{};
  jpeg_destination_mgr destination{};
  OutputFile* file = nullptr;
  std::int64_t at = 0;
  unsigned char* chunk = nullptr;
  bool created = false;
  JpegWriteState() = default;
  JpegWriteState(const JpegWriteState&) = delete;
  JpegWriteState& operator=(const JpegWriteState&) = delete;
  ~JpegWriteState() {
    if (created) jpeg_destroy_compress(&cinfo);
  }
};

JpegWriteState* state_of(j_common_ptr cinfo) { return static_cast<JpegWriteState*>(cinfo->client_data); }

void on_message(j_common_ptr, int) {}

void on_init(j_compress_ptr cinfo) {
  JpegWriteState* s = state_of(reinterpret_cast<j_common_ptr>(cinfo));
  s->destination.next_output_byte = s->chunk;
  s->destination.free_in_buffer = kChunk;
}

boolean on_full(j_compress_ptr cinfo) {
  JpegWriteState* s = state_of(reinterpret_cast<j_common_ptr>(cinfo));
  s->file->write_at(s->at, s->chunk, kChunk);
  s->at += static_cast<std::int64_t>(kChunk);
  on_init(cinfo);
  return TRUE;
}

void on_term(j_compress_ptr cinfo) {
  JpegWriteState* s = state_of(reinterpret_cast<j_common_ptr>(cinfo));
  const std::size_t n = kChunk - s->destination.free_in_buffer;
  s->file->write_at(s->at, s->chunk, n);
  s->at += static_cast<std::int64_t>(n);
}

bool guarded_start(JpegWriteState* s, int width, int height, int components, int quality) {
  return guarded(s->jump, [=] {
    jpeg_create_compress(&s->cinfo);
    s->created = true;
    s->destination.init_destination = on_init;
    s->destination.empty_output_buffer = on_full;
    s->destination.term_destination = on_term;
    s->cinfo.dest = &s->destination;
    s->cinfo.image_width = static_cast<JDIMENSION>(width);
    s->cinfo.image_height = static_cast<JDIMENSION>(height);
    s->cinfo.input_components = components;
    s->cinfo.in_color_space = components == 1 ? JCS_GRAYSCALE : JCS_RGB;
    jpeg_set_defaults(&s->cinfo);
    jpeg_set_quality(&s->cinfo, quality, TRUE);
    jpeg_start_compress(&s->cinfo, TRUE);
  });
}

// The quality: "jpeg:Q" in WriteOptions::compression overrides jpeg_quality, as OpenImageIO did.
int quality_of(const EncodeSpec& spec) {
  int quality = spec.jpeg_quality;
  const std::string& c = spec.compression;
  if (c.size() > 5 && c.compare(0, 5, "jpeg:") == 0) quality = std::atoi(c.c_str() + 5);
  return std::clamp(quality, 1, 100);
}

class JpegEncoder final : public Encoder {
 public:
  std::string format_name() const override { return "jpeg"; }
  std::string compression_refusal(const std::string& compression) const override {
    const bool quality = compression.size() > 5 && compression.compare(0, 5, "jpeg:") == 0;
    return quality ? std::string() : "jpeg:QUALITY only (or --quality)";
  }

  void open(const std::string& path, const EncodeSpec& spec) override {
    file_ = open_written(path);
    chunk_.resize(kChunk);
    s_.chunk = chunk_.data();
    s_.file = file_.get();
    s_.cinfo.err = jpeg_errors(s_, on_message);
    s_.cinfo.client_data = &s_;
    given_ = spec.channels;
    components_ = spec.channels >= 3 ? 3 : 1;  // extra channels are dropped, as OpenImageIO does
    width_ = spec.width;
    if (!guarded_start(&s_, spec.width, spec.height, components_, quality_of(spec))) throw error();
  }

  SampleType stored() const override { return SampleType::UInt8; }
  bool integer_file() const override { return true; }

  void write(int y0, int y1, const void* rows) override {
    const auto* src = static_cast<const unsigned char*>(rows);
    const std::size_t in_row = static_cast<std::size_t>(width_) * given_;
    std::vector<unsigned char*> pointers(static_cast<std::size_t>(y1 - y0));
    if (given_ != components_) {
      packed_.resize(static_cast<std::size_t>(width_) * components_ * pointers.size());
      for (int y = 0; y < y1 - y0; ++y)
        for (int x = 0; x < width_; ++x)
          for (int c = 0; c < components_; ++c)
            packed_[(static_cast<std::size_t>(y) * width_ + x) * components_ + c] = src[y * in_row + x * given_ + c];
      for (int y = 0; y < y1 - y0; ++y) pointers[y] = packed_.data() + static_cast<std::size_t>(y) * width_ * components_;
    } else {
      for (int y = 0; y < y1 - y0; ++y) pointers[y] = const_cast<unsigned char*>(src + y * in_row);
    }
    const auto scanlines = [this](JSAMPARRAY at, JDIMENSION n) { return jpeg_write_scanlines(&s_.cinfo, at, n); };
    if (!guarded(s_.jump, [&] { return all_scanlines(s_, pointers.data(), y1 - y0, scanlines); })) throw error();
    check_written(*file_);
  }

  void close() override {
    if (!guarded(s_.jump, [this] { jpeg_finish_compress(&s_.cinfo); })) throw error();
    close_written(*file_);
  }

 private:
  CodecError error() const { return write_error(file_.get(), s_.message); }

  std::unique_ptr<OutputFile> file_;
  std::vector<unsigned char> chunk_, packed_;
  JpegWriteState s_;  // after the file and chunk: destroyed before them
  int given_ = 0, components_ = 0, width_ = 0;
};

}  // namespace

std::unique_ptr<Encoder> create_jpeg_encoder() { return std::make_unique<JpegEncoder>(); }

}  // namespace gdp::io
