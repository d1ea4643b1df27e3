#include "data/formats/atomic_file.h"

#include <filesystem>
#include <fstream>

#include "data/input_error.h"

namespace adugs::data {

void writeTextFileAtomically(const std::string& path, const std::string& content) {
  const std::string tmp = path + ".tmp";
  {
    std::ofstream out(tmp, std::ios::trunc | std::ios::binary);
    out << content;
    out.flush();
    if (!out) throw InputError(path, 0, "", "cannot write " + tmp);
  }
  std::error_code ec;
  std::filesystem::rename(tmp, path, ec);
  if (ec) throw InputError(path, 0, "", "cannot rename " + tmp + " to it: " + ec.message());
}

}  // namespace adugs::data
