// `gdp convert`: stream an image through gdp's reader and writer (the I/O floor for timings).
#include "cli_common.h"
#include "commands.h"
#include "size_guard.h"
#include "gdp/image_stream.h"

namespace gdp::cli {
namespace {

class Convert final : public Command {
 public:
  explicit Convert(CLI::App& root) {
    app = root.add_subcommand("convert", "read and write an image through gdp's I/O path");
    app->add_option("input", input_, "input image")->required();
    app->add_option("-o,--output", output_, "output image")->required();
    add_common_options(*app, common_, false);
  }

  int run() override {
    Stats stats("convert");
    guard_sizes(common_, nullptr);
    ImageFileReader in(input_);
    ImageFileWriter out(output_, in.width(), in.height(), in.channels(), write_options(common_, in.info()));
    stats.time("total", [&] {
      std::vector<float> row(static_cast<std::size_t>(in.width()) * in.channels());
      for (int y = 0; y < in.height(); ++y) {
        in.read_row(y, row);
        out.write_row(y, row);
      }
      out.commit();
    });
    stats.image(in.width(), in.height(), in.channels());
    stats.write(common_.stats_path);
    return 0;
  }

 private:
  std::string input_, output_;
  CommonOptions common_;
};

}  // namespace

std::unique_ptr<Command> make_convert(CLI::App& root) { return std::make_unique<Convert>(root); }

}  // namespace gdp::cli
