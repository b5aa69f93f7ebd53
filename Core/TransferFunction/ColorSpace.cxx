// ColorSpace.cxx: vtkMath's colour conversions and vtkColorTransferFunction's interpolation.
#include "TransferFunction/ColorSpace.h"

#include "Common/Error.h"

#include <algorithm>
#include <cmath>

namespace ddg
{

ColorSpace parseColorSpace(const std::string& name)
{
  if (name == "RGB")
    return ColorSpace::RGB;
  if (name == "HSV")
    return ColorSpace::HSV;
  if (name == "Lab" || name == "CIELAB")
    return ColorSpace::Lab;
  if (name == "Diverging")
    return ColorSpace::Diverging;
  if (name == "Step")
    return ColorSpace::Step;
  throw Error(
    "unsupported ColorSpace '" + name + "' (RGB, HSV, Lab, Diverging and Step are supported)");
}

const char* colorSpaceName(ColorSpace space)
{
  switch (space)
  {
    case ColorSpace::RGB:
      return "RGB";
    case ColorSpace::HSV:
      return "HSV";
    case ColorSpace::Lab:
      return "Lab";
    case ColorSpace::Diverging:
      return "Diverging";
    case ColorSpace::Step:
      return "Step";
  }
  return "RGB";
}

// --- vtkMath conversions ---------------------------------------------------------------------

RGB rgbToHsv(const RGB& c)
{
  const double r = c[0], g = c[1], b = c[2];
  const double mx = std::max({ r, g, b });
  const double mn = std::min({ r, g, b });
  const double v = mx;
  const double s = v > 0 ? (mx - mn) / mx : 0.0;
  double h = 0;
  if (s > 0)
  {
    const double d = mx - mn;
    if (r == mx)
      h = (g - b) / 6.0 / d;
    else if (g == mx)
      h = 1.0 / 3.0 + (b - r) / 6.0 / d;
    else
      h = 2.0 / 3.0 + (r - g) / 6.0 / d;
    if (h < 0)
      h += 1.0;
  }
  return { h, s, v };
}

RGB hsvToRgb(const RGB& hsv)
{
  const double h = hsv[0], s = hsv[1], v = hsv[2];
  const double onethird = 1.0 / 3.0, onesixth = 1.0 / 6.0, twothird = 2.0 / 3.0,
               fivesixth = 5.0 / 6.0;
  double r, g, b;
  if (h > onesixth && h <= onethird) // green/red
  {
    g = 1.0;
    r = (onethird - h) / onesixth;
    b = 0.0;
  }
  else if (h > onethird && h <= 0.5) // green/blue
  {
    g = 1.0;
    b = (h - onethird) / onesixth;
    r = 0.0;
  }
  else if (h > 0.5 && h <= twothird) // blue/green
  {
    b = 1.0;
    g = (twothird - h) / onesixth;
    r = 0.0;
  }
  else if (h > twothird && h <= fivesixth) // blue/red
  {
    b = 1.0;
    r = (h - twothird) / onesixth;
    g = 0.0;
  }
  else if (h > fivesixth && h <= 1.0) // red/blue
  {
    r = 1.0;
    b = (1.0 - h) / onesixth;
    g = 0.0;
  }
  else // red/green
  {
    r = 1.0;
    g = h / onesixth;
    b = 0.0;
  }
  return { (s * r + 1.0 - s) * v, (s * g + 1.0 - s) * v, (s * b + 1.0 - s) * v };
}

namespace
{
constexpr double kRefX = 0.9505, kRefY = 1.000, kRefZ = 1.089;

double linearize(double c)
{
  return c > 0.04045 ? std::pow((c + 0.055) / 1.055, 2.4) : c / 12.92;
}
double delinearize(double c)
{
  return c > 0.0031308 ? 1.055 * std::pow(c, 1.0 / 2.4) - 0.055 : 12.92 * c;
}
double labF(double v)
{
  return v > 0.008856 ? std::cbrt(v) : 7.787 * v + 16.0 / 116.0;
}
double labFInv(double f)
{
  const double f3 = f * f * f;
  return f3 > 0.008856 ? f3 : (f - 16.0 / 116.0) / 7.787;
}
} // namespace

RGB rgbToLab(const RGB& c)
{
  const double r = linearize(c[0]), g = linearize(c[1]), b = linearize(c[2]);
  const double x = 0.4124 * r + 0.3576 * g + 0.1805 * b;
  const double y = 0.2126 * r + 0.7152 * g + 0.0722 * b;
  const double z = 0.0193 * r + 0.1192 * g + 0.9505 * b;
  const double fx = labF(x / kRefX), fy = labF(y / kRefY), fz = labF(z / kRefZ);
  return { 116.0 * fy - 16.0, 500.0 * (fx - fy), 200.0 * (fy - fz) };
}

RGB rgbToLab(const RGB& c, double jacobian[3][3])
{
  // d linearize / dc and d labF / dv, piece by piece as the functions themselves
  auto dLinearize = [](double v)
  { return v > 0.04045 ? 2.4 / 1.055 * std::pow((v + 0.055) / 1.055, 1.4) : 1.0 / 12.92; };
  auto dLabF = [](double v)
  { return v > 0.008856 ? 1.0 / (3.0 * std::cbrt(v) * std::cbrt(v)) : 7.787; };
  static constexpr double m[3][3] = { { 0.4124, 0.3576, 0.1805 }, { 0.2126, 0.7152, 0.0722 },
    { 0.0193, 0.1192, 0.9505 } };
  static constexpr double ref[3] = { kRefX, kRefY, kRefZ };
  const double lin[3] = { linearize(c[0]), linearize(c[1]), linearize(c[2]) };
  double f[3], df[3][3]; // f(x / ref) and its derivative with respect to rgb
  for (int i = 0; i < 3; ++i)
  {
    const double v = (m[i][0] * lin[0] + m[i][1] * lin[1] + m[i][2] * lin[2]) / ref[i];
    f[i] = labF(v);
    for (int j = 0; j < 3; ++j)
      df[i][j] = dLabF(v) * m[i][j] / ref[i] * dLinearize(c[j]);
  }
  for (int j = 0; j < 3; ++j)
  {
    jacobian[0][j] = 116.0 * df[1][j];
    jacobian[1][j] = 500.0 * (df[0][j] - df[1][j]);
    jacobian[2][j] = 200.0 * (df[1][j] - df[2][j]);
  }
  return { 116.0 * f[1] - 16.0, 500.0 * (f[0] - f[1]), 200.0 * (f[1] - f[2]) };
}

RGB labToRgb(const RGB& lab)
{
  const double fy = (lab[0] + 16.0) / 116.0;
  const double fx = lab[1] / 500.0 + fy;
  const double fz = fy - lab[2] / 200.0;
  const double x = kRefX * labFInv(fx), y = kRefY * labFInv(fy), z = kRefZ * labFInv(fz);
  double r = 3.2406 * x - 1.5372 * y - 0.4986 * z;
  double g = -0.9689 * x + 1.8758 * y + 0.0415 * z;
  double b = 0.0557 * x - 0.2040 * y + 1.0570 * z;
  r = delinearize(r);
  g = delinearize(g);
  b = delinearize(b);
  const double mx = std::max({ r, g, b });
  if (mx > 1.0)
  {
    r /= mx;
    g /= mx;
    b /= mx;
  }
  return { std::max(r, 0.0), std::max(g, 0.0), std::max(b, 0.0) };
}

// --- Moreland's diverging (Msh) interpolation, as vtkColorTransferFunction ----------------------

namespace
{

RGB labToMsh(const RGB& lab)
{
  const double m = std::sqrt(lab[0] * lab[0] + lab[1] * lab[1] + lab[2] * lab[2]);
  const double s = m > 0.001 ? std::acos(lab[0] / m) : 0.0;
  const double h = s > 0.001 ? std::atan2(lab[2], lab[1]) : 0.0;
  return { m, s, h };
}

RGB mshToLab(const RGB& msh)
{
  return { msh[0] * std::cos(msh[1]), msh[0] * std::sin(msh[1]) * std::cos(msh[2]),
    msh[0] * std::sin(msh[1]) * std::sin(msh[2]) };
}

double angleDiff(double a1, double a2)
{
  double d = std::abs(a1 - a2);
  while (d >= 2 * M_PI)
    d -= 2 * M_PI;
  if (d > M_PI)
    d = 2 * M_PI - d;
  return d;
}

double adjustHue(const RGB& msh, double unsatM)
{
  if (msh[0] >= unsatM - 0.1)
  {
    return msh[2];
  }
  const double spin =
    msh[1] * std::sqrt(unsatM * unsatM - msh[0] * msh[0]) / (msh[0] * std::sin(msh[1]));
  return msh[2] > -0.3 * M_PI ? msh[2] + spin : msh[2] - spin;
}

RGB interpolateDiverging(double s, const RGB& rgb1, const RGB& rgb2)
{
  RGB msh1 = labToMsh(rgbToLab(rgb1));
  RGB msh2 = labToMsh(rgbToLab(rgb2));
  if (msh1[1] > 0.05 && msh2[1] > 0.05 && angleDiff(msh1[2], msh2[2]) > 0.33 * M_PI)
  {
    const double mMid = std::max({ 88.0, msh1[0], msh2[0] });
    if (s < 0.5)
    {
      msh2 = { mMid, 0.0, 0.0 };
      s = 2.0 * s;
    }
    else
    {
      msh1 = { mMid, 0.0, 0.0 };
      s = 2.0 * s - 1.0;
    }
  }
  if (msh1[1] < 0.05 && msh2[1] > 0.05)
  {
    msh1[2] = adjustHue(msh2, msh1[0]);
  }
  else if (msh2[1] < 0.05 && msh1[1] > 0.05)
  {
    msh2[2] = adjustHue(msh1, msh2[0]);
  }
  RGB msh{};
  for (int i = 0; i < 3; ++i)
  {
    msh[i] = (1 - s) * msh1[i] + s * msh2[i];
  }
  return labToRgb(mshToLab(msh));
}

} // namespace

RGB interpolateColor(ColorSpace space, bool hsvWrap, double s, const RGB& a, const RGB& b)
{
  switch (space)
  {
    case ColorSpace::RGB:
      return { (1 - s) * a[0] + s * b[0], (1 - s) * a[1] + s * b[1], (1 - s) * a[2] + s * b[2] };
    case ColorSpace::Step:
      return b;
    case ColorSpace::HSV:
    {
      RGB h1 = rgbToHsv(a), h2 = rgbToHsv(b);
      if (hsvWrap && std::abs(h1[0] - h2[0]) > 0.5)
      {
        if (h1[0] > h2[0])
          h1[0] -= 1.0;
        else
          h2[0] -= 1.0;
      }
      RGB h{ (1 - s) * h1[0] + s * h2[0], (1 - s) * h1[1] + s * h2[1],
        (1 - s) * h1[2] + s * h2[2] };
      if (h[0] < 0)
        h[0] += 1.0;
      return hsvToRgb(h);
    }
    case ColorSpace::Lab:
    {
      const RGB l1 = rgbToLab(a), l2 = rgbToLab(b);
      return labToRgb(
        { (1 - s) * l1[0] + s * l2[0], (1 - s) * l1[1] + s * l2[1], (1 - s) * l1[2] + s * l2[2] });
    }
    case ColorSpace::Diverging:
      return interpolateDiverging(s, a, b);
  }
  return a;
}

} // namespace ddg
