// The gdp subcommands: each registers its flags on the root app and runs when chosen.
#pragma once

#include <memory>

#include <CLI/CLI.hpp>

namespace gdp::cli {

class Command {
 public:
  virtual ~Command() = default;
  virtual int run() = 0;
  // True for commands whose solve runs under mpirun (band schedule, gathered output).
  virtual bool runs_under_mpi() const { return false; }
  CLI::App* app = nullptr;
};

std::unique_ptr<Command> make_stitch(CLI::App& root);
std::unique_ptr<Command> make_sharpen(CLI::App& root, bool smooth);
std::unique_ptr<Command> make_reconstruct(CLI::App& root);
std::unique_ptr<Command> make_convert(CLI::App& root);
std::unique_ptr<Command> make_sphere(CLI::App& root);
std::unique_ptr<Command> make_tonemap(CLI::App& root);
std::unique_ptr<Command> make_clone(CLI::App& root);
std::unique_ptr<Command> make_sky(CLI::App& root);
std::unique_ptr<Command> make_blend(CLI::App& root);

}  // namespace gdp::cli
