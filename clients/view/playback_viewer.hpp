// rigid-view FILE: serves a recording (recording_source.hpp) to the page instead of the bus. The
// same server, page and frames as live; a pump sends the state the playback clock
// (playback_clock.hpp) is at, at most kFrameRate times a second and only when it changed, with the
// recorded wrenches acting on it when they differ from the last ones sent (the 'wrenches' message
// of live mode, at most kMaxWrenchesShown), and the pages' play, pause, seek and speed move that
// clock (one clock for every page: they watch the same playback).
#pragma once

#include <filesystem>

#include "view_options.hpp"

namespace rigid::view {

// Loads options.file, serves it until SIGINT/SIGTERM and returns the exit status (1: the file
// cannot be played or the server cannot start, with one line on stderr).
int serve_recording(const ViewOptions& options, const std::filesystem::path& web_dir);

}  // namespace rigid::view
