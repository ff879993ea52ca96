#include "lambert/load/photometry_file.h"

#include "lambert/core/text.h"

namespace lambert {

Result<Photometry> readPhotometry(const std::string& path) {
  return lowercaseExtension(path) == ".ldt" ? readEulumdat(path) : readIes(path);
}

}  // namespace lambert
