#pragma once
// Recordings for the OpenNI2 tests, made by the real library from its Dummy device. Run in
// a child process (record_dummy_oni_main.cpp): OpenNI's Recorder and the Dummy driver
// sometimes deadlock or crash (about one recording in fifteen here), and a test must not.
#include <filesystem>
#include <string>

namespace probeless::testing {

// Records about `frames` frames of the Dummy device's colour and depth (320x240@30) into
// `path` with openni::Recorder, then makes the file playable (below). Returns "" or why not.
std::string record_dummy_oni(const std::filesystem::path& path, int frames);

// OpenNI2's recorder writes an "xnCropping" property only for streams that report cropping,
// which the Dummy device's do not, and OpenNI2's player (libOniFile) drops every frame of a
// stream without that property. This rewrites each stream's "xnIsGenerating" record (an
// OpenNI 1.x leftover the OpenNI2 player ignores; 59 bytes) in place as an "xnCropping"
// record of the same size with cropping off, so no offset in the file moves. Returns how
// many records it rewrote.
int add_cropping_records(const std::filesystem::path& path);

}  // namespace probeless::testing
