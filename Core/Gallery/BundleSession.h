// BundleSession.h: a model bundle opened once for a volume — the volume, the model, its outline
// and the gallery over them — as every front end (the ddg program, the filters and through them
// the panel and pvpython) uses it.
#pragma once

#include "Gallery/Gallery.h"
#include "Volume/Volume.h"

#include <cstdint>
#include <functional>
#include <memory>
#include <string>

namespace ddg
{

/// A bundle directory opened for a volume: the model (refused when it was trained on another
/// volume: fingerprint), its outline latents (`outline.bin`) and the gallery over them.
class BundleSession
{
public:
  /// Throws ddg::Error as NeuralDesignModel::loadBundle and readLatentSet do; a missing outline
  /// names the command that builds it (`volumeHint` stands for the volume in that command).
  BundleSession(
    const std::string& bundleDir, Volume volume, const std::string& volumeHint = "VOLUME");
  /// The bundle for a volume given by its fingerprint (volumeFingerprint) and what it can do
  /// (DesignVolume: e.g. one split over ranks): the gallery renders through `volume`.
  BundleSession(const std::string& bundleDir, const std::string& fingerprint,
    std::shared_ptr<const DesignVolume> volume, const std::string& volumeHint = "VOLUME");
  ~BundleSession();
  BundleSession(const BundleSession&) = delete;
  BundleSession& operator=(const BundleSession&) = delete;

  const std::string& directory() const { return Directory; }
  /// The volume in this process (throws ddg::Error for a session opened by fingerprint).
  const Volume& volume() const;
  NeuralDesignModel& model() { return *Model; }
  DesignGallery& gallery() { return *Gallery; }
  const DesignGallery& gallery() const { return *Gallery; }
  const std::string& fingerprint() const { return Fingerprint; }
  bool hasVolume() const { return Vol != nullptr; }

  /// bundleStamp of the directory when the session opened it.
  std::uint64_t stamp() const { return Stamp; }

  double outlineReadMs() const { return ReadMs; } ///< reading outline.bin
  double outlinePcaMs() const { return PcaMs; }   ///< the outline's PCA (building the gallery)

private:
  LatentSet openBundle(const std::string& volumeHint); // the model, then the outline's latents
  void attachQueryKey();                               // query_key.json, when the bundle has one

  std::string Directory, Fingerprint;
  std::unique_ptr<Volume> Vol;
  std::unique_ptr<NeuralDesignModel> Model;
  std::shared_ptr<const DesignVolume> Space; // by fingerprint
  std::unique_ptr<DesignGallery> Gallery;
  double ReadMs = 0, PcaMs = 0;
  std::uint64_t Stamp = 0;
};

/// A number that changes when any file directly in `bundleDir` is added, removed, resized or
/// rewritten (names, sizes and modification times hashed; 0 when it cannot be listed): a bundle
/// rebuilt in place is opened again.
std::uint64_t bundleStamp(const std::string& bundleDir);

/// The session of the bundle a front end asks for again and again (a filter re-executing):
/// opened on first use and reopened only when the bundle directory, its files (bundleStamp) or
/// the volume's version (any number that changes when the volume's data does) changes. Holds one
/// session.
class BundleSessionCache
{
public:
  /// Throws ddg::Error for an empty directory ("no ModelDirectory set") and as BundleSession does.
  BundleSession& get(const std::string& bundleDir, std::uint64_t volumeVersion,
    const std::function<Volume()>& loadVolume);
  /// The session by fingerprint (a volume split over ranks), reopened when the directory, the
  /// fingerprint or the volume object changes.
  BundleSession& get(const std::string& bundleDir, const std::string& fingerprint,
    const std::shared_ptr<const DesignVolume>& volume);
  void clear() { Session.reset(); }
  /// The session last opened (nullptr: none, or the last get threw).
  const BundleSession* current() const { return Session.get(); }

private:
  std::unique_ptr<BundleSession> Session;
  std::uint64_t Version = 0;
};

} // namespace ddg
