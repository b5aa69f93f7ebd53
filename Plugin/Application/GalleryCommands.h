// GalleryCommands.h: registers the gallery subcommands of `ddg` (outline, gallery, query,
// export) on the program's CLI11 app.
#pragma once

#include <CLI/CLI.hpp>

#include <functional>

/// Adds the subcommands to `app`; the returned function runs the one that was parsed and
/// returns its exit code, or -1 when none of them was. Errors are thrown as ddg::Error.
std::function<int()> addGalleryCommands(CLI::App& app);
