// OpenImageIO IOProxy methods forwarded to io::OutputFile.
#include "oiio_module/checked_file.h"

namespace gdp::io {

CheckedFile::CheckedFile(const std::string& path) : IOProxy(path, Write), file_(path) {
  if (file_.failed()) m_mode = Closed;
}

CheckedFile::~CheckedFile() { CheckedFile::close(); }

void CheckedFile::close() {
  file_.close();
  m_mode = Closed;
}

bool CheckedFile::seek(int64_t offset) {
  m_pos = offset;
  return offset >= 0;
}

size_t CheckedFile::read(void* buf, size_t size) {
  const size_t n = file_.read_at(m_pos, buf, size);
  m_pos += static_cast<int64_t>(n);
  return n;
}

size_t CheckedFile::write(const void* buf, size_t size) {
  file_.write_at(m_pos, buf, size);
  m_pos += static_cast<int64_t>(size);
  return size;
}

size_t CheckedFile::pread(void* buf, size_t size, int64_t offset) { return file_.read_at(offset, buf, size); }

size_t CheckedFile::pwrite(const void* buf, size_t size, int64_t offset) {
  file_.write_at(offset, buf, size);
  return size;
}

size_t CheckedFile::size() const { return static_cast<size_t>(file_.size()); }

}  // namespace gdp::io
