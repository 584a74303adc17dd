// `gdp convert`: read and write through gdp's I/O path (the I/O floor for timings).
#include "cli_common.h"
#include "commands.h"

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
    const ReadResult in = stats.time("read", [&] { return read_image(input_); });
    stats.time("write", [&] { write_image(output_, in.image, write_options(common_, in.info)); });
    stats.set("width", std::to_string(in.image.width));
    stats.set("height", std::to_string(in.image.height));
    stats.set("channels", std::to_string(in.image.channels));
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
