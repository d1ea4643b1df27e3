#include "calib/intrinsics/visp_camera_xml.h"

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include <visp3/core/vpCameraParameters.h>
#include <visp3/core/vpXmlParserCamera.h>

#include "calib/text_format.h"
#include "data/formats/atomic_file.h"
#include "data/input_error.h"

namespace adugs::calib {
namespace {

// kdu for x_u = x_d (1 + kdu r_d^2), fitted over the image diagonal (pixels).
double fitKdu(const CalibCamera& c) {
  const double k1 = c.params[4];
  double num = 0, den = 0;
  for (int i = 1; i <= 200; ++i) {
    // Undistorted radius up to the image corner.
    const double u = c.width * i / 200.0 - c.pu(), v = c.height * i / 200.0 - c.pv();
    const double xu = u / c.fu(), yu = v / c.fv();
    const double ru2 = xu * xu + yu * yu;
    const double s = 1 + k1 * ru2;  // distorted = undistorted * s
    const double rd2 = ru2 * s * s;
    // Want 1 / s = 1 + kdu * rd2  ->  kdu * rd2 = 1/s - 1.
    num += rd2 * (1 / s - 1);
    den += rd2 * rd2;
  }
  return den > 0 ? num / den : 0;
}

}  // namespace

void writeVispCameraXml(const std::string& path, const CalibCamera& c,
                        const std::string& camera_name, const std::string& note) {
  namespace fs = std::filesystem;
  if (c.projection != ProjectionModel::kPinhole)
    throw std::invalid_argument("writeVispCameraXml: ViSP has no " + c.modelName() + " camera");
  const std::string tmp = path + ".visp.tmp";
  std::error_code ec;
  fs::remove(tmp, ec);
  vpXmlParserCamera parser;
  vpCameraParameters without;
  without.initPersProjWithoutDistortion(c.fu(), c.fv(), c.pu(), c.pv());
  const unsigned w = static_cast<unsigned>(c.width), h = static_cast<unsigned>(c.height);
  if (parser.save(without, tmp, camera_name, w, h) != vpXmlParserCamera::SEQUENCE_OK)
    throw data::InputError(path, 0, "", "vpXmlParserCamera could not write the camera");
  const bool no_lens = c.model == DistortionModel::kNone;
  const bool radial_only = no_lens || (c.model == DistortionModel::kRadialTangential &&
                                       c.params[5] == 0 && c.params[6] == 0 && c.params[7] == 0);
  if (radial_only) {
    vpCameraParameters with;
    with.initPersProjWithDistortion(c.fu(), c.fv(), c.pu(), c.pv(), no_lens ? 0.0 : c.params[4],
                                    no_lens ? 0.0 : fitKdu(c));
    vpXmlParserCamera again;
    if (again.save(with, tmp, camera_name, w, h) != vpXmlParserCamera::SEQUENCE_OK)
      throw data::InputError(path, 0, "", "vpXmlParserCamera could not write the camera");
  }
  std::ifstream in(tmp);
  std::stringstream text;
  text << in.rdbuf();
  in.close();
  fs::remove(tmp, ec);
  std::string xml = text.str();
  std::string comment =
      "<!-- adugs calib intrinsics: Kalibr model pinhole-" + data::kalibrName(c.model) +
                        ", intrinsics [" + formatDouble(c.fu()) + ", " + formatDouble(c.fv()) +
                        ", " + formatDouble(c.pu()) + ", " + formatDouble(c.pv()) +
                        "], distortion_coeffs [";
  for (int i = 4; i < 8; ++i) comment += (i > 4 ? ", " : "") + formatDouble(c.params[i]);
  comment += "]. ";
  comment += radial_only
                 ? "Radial-only: kud = k1 is exact, kdu is a least-squares inverse."
                 : "ViSP cannot express this distortion: the model below is exact for images "
                   "undistorted with the Kalibr model (see camchain.yaml).";
  if (!note.empty()) {
    // "--" may not appear inside an XML comment.
    std::string safe = note;
    for (size_t at = safe.find("--"); at != std::string::npos; at = safe.find("--", at)) safe.replace(at, 2, "- ");
    comment += "\n" + safe;
  }
  comment += " -->\n";
  const size_t decl = xml.find("?>");
  const size_t at = decl == std::string::npos ? 0 : xml.find('\n', decl) + 1;
  xml.insert(at, comment);
  data::writeTextFileAtomically(path, xml);
}

}  // namespace adugs::calib
