#pragma once
// Colour science for colours given as chromaticities and spectra (MGF's colour model): CIE 1931
// XYZ from a spectrum by the 2° colour matching functions in the multi-lobe Gaussian fit of
// Wyman, Sloan & Shirley 2013 ("Simple analytic approximations to the CIE XYZ color matching
// functions", JCGT 2(2)), black bodies by Planck's law, XYZ that is no real colour moved onto the
// boundary of real chromaticities (the CIE 1931 spectral locus, tabulated every 10 nm, and the
// purple line), and XYZ to linear Rec. 709 RGB scaled so that the equal-energy white E is
// (1, 1, 1).
//
// Cost: a spectrum integrates at 1 nm steps (471 evaluations of the fit). The fit's far tails are
// too inexact for chromaticities there (which is why the locus is tabulated); colours outside
// Rec. 709's gamut are clipped per channel.
#include <functional>
#include <string>

#include "lambert/core/rgb.h"

namespace lambert {

// CIE 1931 XYZ tristimulus values; the default is the equal-energy white E at unit luminance.
struct Xyz {
  double x = 1, y = 1, z = 1;
};

// XYZ of a spectrum given as a function of wavelength (nm), integrated at 1 nm over the visible
// range 360–830 nm; unnormalised.
Xyz integrateSpectrum(const std::function<double(double)>& spectrum);

// Planck's spectral radiance at temperature T (K), up to a constant factor.
double planck(double lambdaNm, double kelvin);

// A colour's CIE XYZ as a real colour at unit luminance; `repair` says what was done to one
// that is not a real colour (empty when nothing was). MGF allows negative spectral samples and
// mixing weights (the CIE daylight basis functions are negative by definition): only what they
// integrate to must be a colour. A negative component is clipped to 0, as RenderPark does; a
// colour with no luminance left (cxy x 0, as RGB-to-xy converters write for pure blue or
// purple) keeps its hue and becomes the most saturated real colour of it, rather than black
// (RenderPark's choice, which loses the reflectance the file gives) or white (which loses the
// hue); one with nothing left at all is white.
Xyz realColour(const Xyz& c, std::string& repair);

// A chromaticity as lambert RGB of Rec. 709 luminance 1, with the equal-energy white (E) at
// (1, 1, 1).
Rgb chromaticityToRgb(const Xyz& c);

}  // namespace lambert
