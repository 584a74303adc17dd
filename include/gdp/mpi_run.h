// Running under mpirun: MPI started for the life of the process, and which rank this process is.
#pragma once

#include <filesystem>
#include <functional>
#include <memory>
#include <string>

#include "gdp/rows.h"

namespace gdp {

struct WriteOptions;

// The process's MPI session (docs/how-bands-work.md, "Running under mpirun"). Constructed once in
// main(): when the process was launched by mpirun (OMPI_COMM_WORLD_SIZE, PMI_SIZE or PMIX_RANK in
// the environment) it starts MPI with MPI_THREAD_MULTIPLE, otherwise it does nothing and the
// process is rank 0 of 1. The band schedule (--bands) then runs `--bands` bands on every rank.
class MpiRun {
 public:
  MpiRun(int& argc, char**& argv);
  ~MpiRun();  // MPI_Finalize, when started
  MpiRun(const MpiRun&) = delete;
  MpiRun& operator=(const MpiRun&) = delete;

  static bool launched();  // started by mpirun (whether or not MPI is initialised yet)
  static int rank();       // 0 without MPI
  static int size();       // 1 without MPI
  // True once every rank has seen the same error in the collective check before a solve:
  // every rank then returns normally (rank 0 prints the message) instead of aborting.
  static bool failed_together();
  // Every rank calls this at the same point with its own error ("" when it has none): returns
  // when no rank has one, else throws the same UsageError on every rank (the lowest failing
  // rank's, failed_together() then true). Without MPI: throws UsageError(error) unless empty.
  static void agree(const std::string& error);
  // Prints "gdp: rank R: why" and ends every rank with exit status 2 (MPI_Abort, the MPI
  // transport's abort path); without MPI it returns and the caller reports the error.
  static void abort(const std::string& why);
  // The writer every rank hands a solve's rows to: without MPI (or with one rank) the file
  // `open_file` opens, at once. Under mpirun with ranks that write only their columns
  // (RowWriter::set_columns, as the band schedule does) rank 0 puts every row together from all
  // ranks' columns and writes it to that file, opened only once the ranks have agreed to solve
  // (set_columns, or the first row): a rank that fails before then, ending them all, leaves no
  // temporary file behind. Other ranks send theirs and never call `open_file`. Rows written whole
  // (no set_columns) go to rank 0's file as they are; other ranks drop theirs.
  using OpenFile = std::function<std::unique_ptr<RowWriter>()>;
  static std::unique_ptr<RowWriter> gather_writer(OpenFile open_file, int width, int height, int channels);
  // gather_writer of the image file `path` (an ImageFileWriter with `options`): the output of
  // every command that writes one file (the CLI's open_output, gdp sky --projected).
  static std::unique_ptr<RowWriter> gather_file(const std::filesystem::path& path, int width, int height, int channels,
                                                const WriteOptions& options);
};

}  // namespace gdp
