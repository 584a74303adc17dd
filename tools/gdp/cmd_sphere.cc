// `gdp sphere to-pq | from-pq | toast`: resample spherical images to and from the PQ layout, and
// cut a PQ image into a WorldWideTelescope TOAST tile pyramid.
#include <cmath>

#include <fmt/format.h>

#include "cli_common.h"
#include "commands.h"
#include "size_guard.h"
#include "gdp/errors.h"
#include "gdp/image_stream.h"
#include "gdp/sphere.h"

namespace gdp::cli {
namespace {

using sphere::Layout;
using sphere::Projection;

class Sphere final : public Command {
 public:
  explicit Sphere(CLI::App& root) {
    app = root.add_subcommand("sphere", "spherical images: PQ layout, equirectangular and cube maps, TOAST tiles");
    app->require_subcommand(1);

    to_pq_ = app->add_subcommand("to-pq", "resample an equirectangular (2:1) or cube-strip (1:6) image to PQ (4:1)");
    to_pq_->add_option("input", input_, "input image")->required();
    to_pq_->add_option("-o,--output", output_, "output PQ image")->required();
    to_pq_->add_option("--height", size_, "PQ height H (width 4H); default: about the input's pixel count, "
                                          "H = m * 2^k with 8 <= m <= 16");
    add_map_options(*to_pq_);

    from_pq_ = app->add_subcommand("from-pq", "resample a PQ image to equirectangular or a cube strip");
    from_pq_->add_option("input", input_, "input PQ image (width 4 x height)")->required();
    from_pq_->add_option("-o,--output", output_, "output image")->required();
    from_pq_->add_option("--format", format_, "equirect (2:1) | cube (vertical strip +X -X +Y -Y +Z -Z)")
        ->required()
        ->check(CLI::IsMember({"equirect", "cube"}));
    from_pq_->add_option("--width", size_, "equirect width, or cube face size; default: about the PQ pixel count");
    add_map_options(*from_pq_);

    toast_ = app->add_subcommand("toast", "write a WorldWideTelescope TOAST tile pyramid from a TOAST PQ image");
    toast_->add_option("input", input_, "PQ image of height 128 * 2^n (TOAST map)")->required();
    toast_->add_option("-o,--output", output_, "output directory (new or empty)")->required();
    toast_->add_option("--levels", levels_, "deepest level written (default: n, where H = 128 * 2^n)");
    toast_->add_option("--name", name_, "data set name in toast.wtml")->capture_default_str();
    for (CLI::App* sub : {to_pq_, from_pq_, toast_}) add_common_options(*sub, common_, false);
  }

  int run() override {
    guard_sizes(common_, nullptr, true);  // resampled in memory
    try {
      if (toast_->parsed()) return run_toast();
      return run_resample(to_pq_->parsed());
    } catch (const UsageError& e) {
      throw UsageError(input_ + ": " + e.what());
    }
  }

 private:
  void add_map_options(CLI::App& cmd) {
    cmd.add_option("--map", map_, "sphere <-> square map of the PQ image: toast | octahedral (equal-area)")
        ->check(CLI::IsMember({"toast", "octahedral"}))
        ->capture_default_str();
    cmd.add_flag("--nearest", nearest_, "nearest neighbour: copy values, never blend (label maps)");
    cmd.add_flag("--sky", sky_, "equirectangular longitude increases to the left (astronomical plate carree)");
    cmd.add_option("--threads", threads_, "threads (default: all cores)");
  }

  int run_resample(bool to_pq) {
    Stats stats(to_pq ? "sphere to-pq" : "sphere from-pq");
    ImageFileReader in(input_);
    const long long pixels = static_cast<long long>(in.width()) * in.height();
    Projection pq{Layout::Pq, sphere::parse_square_map(map_), false}, other{Layout::Equirect, {}, sky_};
    if (to_pq) {
      try {
        other.layout = sphere::guess_layout(in.width(), in.height());
      } catch (const InputError& e) {
        throw InputError(fmt::format("{}: {}", input_, e.what()));
      }
      if (other.layout == Layout::Pq) throw InputError(input_ + ": is already a PQ image (4:1)");
    } else {
      if (in.width() != 4 * in.height())
        throw InputError(fmt::format("{}: {}x{} is not a PQ image (width must be 4 x height)", input_, in.width(),
                                     in.height()));
      other.layout = format_ == "cube" ? Layout::Cube : Layout::Equirect;
    }
    int size = size_;
    if (size <= 0) {
      if (to_pq) size = sphere::default_pq_height(pixels);
      else if (other.layout == Layout::Equirect) size = 2 * static_cast<int>(std::lround(std::sqrt(pixels / 2.0)));
      else size = std::max(1, static_cast<int>(std::lround(std::sqrt(pixels / 6.0))));
    }
    const Layout layout = to_pq ? Layout::Pq : other.layout;
    const long long side = size;
    check_derived_size(fmt::format("{} {}", to_pq ? "--height" : "--width", size),
                       layout == Layout::Pq ? 4 * side : side,
                       layout == Layout::Pq ? side : layout == Layout::Cube ? 6 * side : std::max(1LL, side / 2),
                       in.channels());
    const auto [w, h] = sphere::layout_size(layout, size);
    sphere::ResampleOptions options;
    options.nearest = nearest_;
    options.threads = threads_;
    ImageFileWriter out(output_, w, h, in.channels(), write_options(common_, in.info()));
    stats.time("total", [&] {
      if (to_pq) sphere::resample(in, other, out, pq, w, h, options);
      else sphere::resample(in, pq, out, other, w, h, options);
      out.commit();
    });
    note(common_, fmt::format("{} {}x{} -> {}x{}", to_pq ? "to-pq" : "from-pq", in.width(), in.height(), w, h));
    stats.image(w, h, in.channels());
    stats.write(common_.stats_path);
    return 0;
  }

  int run_toast() {
    Stats stats("sphere toast");
    const ReadResult pq = read_image(input_);
    sphere::ToastPyramidOptions options;
    options.levels = levels_;
    options.name = name_;
    options.write = write_options(common_, pq.info);
    if (!options.write.sample_type || *options.write.sample_type == SampleType::Float ||
        *options.write.sample_type == SampleType::Half)
      options.write.sample_type = SampleType::UInt8;  // PNG tiles
    stats.time("total", [&] { sphere::write_toast_pyramid(pq.image, output_, options); });
    stats.write(common_.stats_path);
    return 0;
  }

  CLI::App *to_pq_ = nullptr, *from_pq_ = nullptr, *toast_ = nullptr;
  std::string input_, output_, format_, map_ = "toast", name_ = "gdp";
  int size_ = 0, levels_ = -1, threads_ = 0;
  bool nearest_ = false, sky_ = false;
  CommonOptions common_;
};

}  // namespace

std::unique_ptr<Command> make_sphere(CLI::App& root) { return std::make_unique<Sphere>(root); }

}  // namespace gdp::cli
