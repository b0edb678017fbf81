#pragma once
// Every subcommand lives in its own apps/cmd_NAME.cpp: it declares its options on a CLI11
// subcommand and returns the function that runs it. The command line only parses arguments and
// calls the libraries; the libraries throw sdm::InputError for bad input (exit code 2).
#include <CLI/CLI.hpp>
#include <functional>
#include <iostream>
#include <nlohmann/json.hpp>
#include <string>

#include "libstm/core/errors.h"

namespace sdm::cli {

struct Command {
  CLI::App* app = nullptr;
  std::function<int()> run;
};

Command add_info_command(CLI::App& parent);
Command add_convert_command(CLI::App& parent);
Command add_repair_command(CLI::App& parent);
Command add_remesh_command(CLI::App& parent);
Command add_render_command(CLI::App& parent);
Command add_encode_command(CLI::App& parent);
Command add_decode_command(CLI::App& parent);
Command add_pose_command(CLI::App& parent);
Command add_roundtrip_command(CLI::App& parent);
Command add_compare_command(CLI::App& parent);
Command add_bench_command(CLI::App& parent);
Command add_skeleton_command(CLI::App& parent);
Command add_primitive_command(CLI::App& parent);
Command add_stm_command(CLI::App& parent);
Command add_remap_command(CLI::App& parent);
Command add_transfer_command(CLI::App& parent);
Command add_correspond_command(CLI::App& parent);

// Progress lines go to stderr, so stdout stays clean for results and --json.
inline void progress(const std::string& line) { std::cerr << line << std::endl; }

// Prints a command's JSON summary on stdout; an object also gets "repair": what repair did to each
// input mesh this run read (load_input in cli_common.h), when it did anything.
void print_json(nlohmann::json j);

}  // namespace sdm::cli
