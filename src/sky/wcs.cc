// The celestial WCS of a header through wcslib: wcspih, wcssub (celestial axes), wcsfix, wcsset, wcsp2s / wcss2p.
#include "sky/wcs.h"

#include <wcslib/wcs.h>
#include <wcslib/wcserr.h>
#include <wcslib/wcsfix.h>
#include <wcslib/wcshdr.h>

#include <algorithm>
#include <vector>

#include <fmt/format.h>

#include "gdp/errors.h"

namespace gdp::sky {

// Conversions run in chunks of this many points, with scratch arrays made per call (76 bytes a
// point): kept per plate, they grew to each plate's largest batch and stayed (docs/sky.md,
// "Memory, bands and mpirun": 0.7 MB a plate, over half the peak heap with 48 plates).
constexpr std::size_t kChunk = 1024;

struct Wcs::Prm {
  wcsprm wcs{};
  bool initialised = false;
  ~Prm() {
    if (initialised) wcsfree(&wcs);
  }
};

namespace {

// The intermediate arrays wcsp2s / wcss2p need, for up to n points.
struct Conversion {
  std::vector<double> pix, img, phi, theta, world;
  std::vector<int> stat;
  explicit Conversion(std::size_t n)
      : pix(2 * n), img(2 * n), phi(n), theta(n), world(2 * n), stat(n) {}
};

}  // namespace

namespace {

std::string trimmed(const char* s) {
  std::string t(s);
  while (!t.empty() && t.back() == ' ') t.pop_back();
  return t;
}

std::string wcslib_message(const wcsprm& w, int status) {
  if (w.err && w.err->msg[0]) return w.err->msg;
  if (status > 0 && status <= WCSERR_NON_SEPARABLE) return wcs_errmsg[status];
  return fmt::format("wcslib status {}", status);
}

}  // namespace

Wcs::Wcs(const std::string& header, int width, int height, const std::string& name)
    : prm_(std::make_unique<Prm>()), width_(width), height_(height) {
  const auto fail = [&](const std::string& problem) { return InputError(fmt::format("{}: {}", name, problem)); };
  wcserr_enable(1);
  std::string cards = header;
  int nreject = 0, nwcs = 0;
  wcsprm* all = nullptr;
  const int status = wcspih(cards.data(), static_cast<int>(cards.size() / 80), WCSHDR_all, 0, &nreject, &nwcs, &all);
  if (status) throw fail(fmt::format("cannot parse the WCS: {}", wcshdr_errmsg[status]));
  // The primary description (alternate ' ') is the first; keep only its celestial axes.
  if (nwcs == 0) {
    wcsvfree(&nwcs, &all);
    throw fail("no celestial WCS in the header (no CTYPE1/CTYPE2 such as RA---TAN/DEC--TAN)");
  }
  int nsub = 2, axes[2] = {WCSSUB_LONGITUDE, WCSSUB_LATITUDE};
  prm_->wcs.flag = -1;
  const int sub = wcssub(1, &all[0], &nsub, axes, &prm_->wcs);
  wcsvfree(&nwcs, &all);
  prm_->initialised = sub == 0;
  if (sub) throw fail(fmt::format("cannot take the celestial axes of the WCS: {}", wcs_errmsg[sub]));
  if (nsub != 2) throw fail("no celestial WCS (CTYPE1/CTYPE2 name no longitude and latitude axes such as RA---TAN/DEC--TAN)");
  if (axes[0] != 1 || axes[1] != 2)
    throw fail(fmt::format("the celestial axes are image axes {} and {}; gdp needs them to be axes 1 and 2", axes[0], axes[1]));
  wcsprm& w = prm_->wcs;
  int naxis[2] = {width, height}, fixes[NWCSFIX];
  wcsfix(7, naxis, &w, fixes);  // informal forms: units, DATE-OBS, NCP/GLS, CD with zeros, ...
  if (const int s = wcsset(&w)) {
    throw fail(fmt::format("WCS rejected ({} = '{}', {} = '{}'): {}", "CTYPE1", trimmed(w.ctype[0]), "CTYPE2",
                           trimmed(w.ctype[1]), wcslib_message(w, s)));
  }
  if (w.lng != 0 || w.lat != 1) throw fail("CTYPE1 must be the longitude axis and CTYPE2 the latitude axis");
  const bool cd = (w.altlin & 2) && !(w.altlin & 1);  // CDi_j given (and no PCi_j)
  const double* m = cd ? w.cd : w.pc;
  if ((m[0] * m[3] - m[1] * m[2]) * (cd ? 1.0 : w.cdelt[0] * w.cdelt[1]) == 0.0)
    throw fail("WCS rejected: the pixel-to-sky matrix (CDi_j, or PCi_j with CDELTi) is singular");
  frame_ = trimmed(w.lngtyp);
  projection_ = trimmed(w.cel.prj.code);
}

Wcs::~Wcs() = default;

void Wcs::pixel_to_sky(std::span<const double> xy, std::span<double> sky, std::span<unsigned char> ok) const {
  Conversion p(std::min(kChunk, ok.size()));
  for (std::size_t k0 = 0; k0 < ok.size(); k0 += kChunk) {
    const std::size_t n = std::min(kChunk, ok.size() - k0);
    for (std::size_t k = 0; k < n; ++k) {
      p.pix[2 * k] = xy[2 * (k0 + k)] + 0.5;
      p.pix[2 * k + 1] = height_ + 0.5 - xy[2 * (k0 + k) + 1];
    }
    const int s = wcsp2s(&prm_->wcs, static_cast<int>(n), 2, p.pix.data(), p.img.data(), p.phi.data(), p.theta.data(),
                         p.world.data(), p.stat.data());
    for (std::size_t k = 0; k < n; ++k) {
      ok[k0 + k] = (s == 0 || s == WCSERR_BAD_PIX) && p.stat[k] == 0;
      sky[2 * (k0 + k)] = p.world[2 * k];
      sky[2 * (k0 + k) + 1] = p.world[2 * k + 1];
    }
  }
}

void Wcs::sky_to_pixel(std::span<const double> sky, std::span<double> xy, std::span<unsigned char> ok) const {
  Conversion p(std::min(kChunk, ok.size()));
  for (std::size_t k0 = 0; k0 < ok.size(); k0 += kChunk) {
    const std::size_t n = std::min(kChunk, ok.size() - k0);
    std::copy_n(sky.begin() + 2 * k0, 2 * n, p.world.begin());
    const int s = wcss2p(&prm_->wcs, static_cast<int>(n), 2, p.world.data(), p.phi.data(), p.theta.data(), p.img.data(),
                         p.pix.data(), p.stat.data());
    for (std::size_t k = 0; k < n; ++k) {
      ok[k0 + k] = (s == 0 || s == WCSERR_BAD_WORLD) && p.stat[k] == 0;
      xy[2 * (k0 + k)] = p.pix[2 * k] - 0.5;
      xy[2 * (k0 + k) + 1] = height_ + 0.5 - p.pix[2 * k + 1];
    }
  }
}

bool Wcs::one_point(bool to_sky, double a, double b, double& u, double& v) const {
  const double in[2] = {a, b};
  double out[2];
  unsigned char ok = 0;
  if (to_sky) pixel_to_sky(in, out, {&ok, 1});
  else sky_to_pixel(in, out, {&ok, 1});
  u = out[0];
  v = out[1];
  return ok;
}

bool Wcs::pixel_to_sky(double x, double y, double& lon, double& lat) const { return one_point(true, x, y, lon, lat); }

bool Wcs::sky_to_pixel(double lon, double lat, double& x, double& y) const { return one_point(false, lon, lat, x, y); }

}  // namespace gdp::sky
