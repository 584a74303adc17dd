// The OpenImageIO I/O proxy over io::OutputFile, so OpenImageIO's writers never see a failed write.
#pragma once

#include <OpenImageIO/filesystem.h>

#include <cstdint>
#include <string>

#include "io/output_file.h"

namespace gdp::io {

// Every write "succeeds" (see io::OutputFile); the owner turns file().problem() into an error.
// (OpenImageIO 2.4's JPEG writer, given a proxy, compresses the whole file into memory and
// writes it at close(); the other writers write as they go.)
class CheckedFile final : public OIIO::Filesystem::IOProxy {
 public:
  explicit CheckedFile(const std::string& path);  // opens an existing file for writing, truncated
  ~CheckedFile() override;
  CheckedFile(const CheckedFile&) = delete;
  CheckedFile& operator=(const CheckedFile&) = delete;

  const char* proxytype() const override { return "gdp-checked"; }
  void close() override;
  bool seek(int64_t offset) override;
  size_t read(void* buf, size_t size) override;
  size_t write(const void* buf, size_t size) override;
  size_t pread(void* buf, size_t size, int64_t offset) override;
  size_t pwrite(const void* buf, size_t size, int64_t offset) override;
  size_t size() const override;
  void flush() const override {}

  const OutputFile& file() const { return file_; }

 private:
  OutputFile file_;
};

}  // namespace gdp::io
