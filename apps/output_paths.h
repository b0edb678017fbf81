#pragma once
// Checks every output a command names before it does any work, so that a bad companion output
// (--png in a missing folder) does not fail after the main output was written, and an output that
// would destroy something (the input itself, a device, a folder) is refused (DECISIONS 1, "Hostile input").
#include <CLI/CLI.hpp>
#include <filesystem>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace sdm::cli {

// The options that name files the command writes (long names without dashes).
bool is_output_option(const std::string& long_name);

// Throws InputError naming the option and the path when an output of the parsed `command` is a
// folder, exists and is not a regular file (a device such as /dev/null, a pipe), lies in a folder
// that does not exist, is the same file as one of the command's inputs, or is named twice.
void check_output_paths(const CLI::App& command);

// The outputs of the parsed command as they are before it runs (modification time, or none when
// missing), so that a run that fails halfway leaves none of its outputs behind.
using OutputsBefore = std::vector<std::pair<std::string, std::optional<std::filesystem::file_time_type>>>;
OutputsBefore record_outputs(const CLI::App& command);
// Removes each output that the failed run created or rewrote.
void remove_written_outputs(const OutputsBefore& before);

}  // namespace sdm::cli
