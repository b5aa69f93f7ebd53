// ColorSpace.h: the colour spaces ParaView interpolates colour maps in, and conversions.
#pragma once

#include <array>
#include <string>

namespace ddg
{

/// vtkColorTransferFunction's colour spaces (ParaView preset "ColorSpace" names in brackets):
/// RGB ["RGB"], HSV ["HSV"], Lab ["Lab" / "CIELAB"], Diverging ["Diverging", Moreland's Msh],
/// Step ["Step"]. "Lab/CIEDE2000" is not supported (reading it throws ddg::Error).
enum class ColorSpace
{
  RGB,
  HSV,
  Lab,
  Diverging,
  Step
};

/// Parses a preset's "ColorSpace" string; throws ddg::Error on an unsupported name.
ColorSpace parseColorSpace(const std::string& name);
/// The preset name of a colour space ("RGB", "HSV", "Lab", "Diverging", "Step").
const char* colorSpaceName(ColorSpace space);

using RGB = std::array<double, 3>;

/// Conversions as vtkMath does them (sRGB with its gamma, D65 white, Lab in CIE units).
RGB rgbToHsv(const RGB& rgb);
RGB hsvToRgb(const RGB& hsv);
RGB rgbToLab(const RGB& rgb);
RGB labToRgb(const RGB& lab);
/// rgbToLab and its Jacobian: jacobian[i][j] = d lab_i / d rgb_j (the left derivative at the
/// kinks of sRGB's and Lab's piecewise curves).
RGB rgbToLab(const RGB& rgb, double jacobian[3][3]);

/// Interpolates between two colours at s in [0, 1] as vtkColorTransferFunction does for a
/// segment with sharpness < 0.01 (after the midpoint remapping of s).
RGB interpolateColor(ColorSpace space, bool hsvWrap, double s, const RGB& a, const RGB& b);

} // namespace ddg
