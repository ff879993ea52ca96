#pragma once
// The readers of a luminaire's photometric file: IES LM-63 (load/ies.cpp) and EULUMDAT
// (load/eulumdat.cpp), into the candela model of light/photometry.h.
#include <string>

#include "lambert/core/error.h"
#include "lambert/light/photometry.h"

namespace lambert {

// Reads an IES LM-63 file (1986/1991 without a header line, 1995, 2002, 2019). Type C only; types
// A and B are refused with a message saying how to convert them. TILT=<file> is read relative to
// the file. Repairs it understands (negative candela, angles a little out of order, trailing
// values) are warnings naming file:line; the rest is an error naming file:line and what to do.
Result<Photometry> readIes(const std::string& path);
Result<Photometry> parseIes(const std::string& text, const std::string& path);

// Reads a EULUMDAT (.ldt) file: the fixed line layout, symmetry Isym 0–4, cd/klm converted to cd
// through the first lamp set's flux.
Result<Photometry> readEulumdat(const std::string& path);
Result<Photometry> parseEulumdat(const std::string& text, const std::string& path);

// readEulumdat for .ldt, readIes otherwise.
Result<Photometry> readPhotometry(const std::string& path);

}  // namespace lambert
