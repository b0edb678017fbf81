#pragma once
// Every subcommand lives in its own apps/cmd_NAME.cpp: it declares its options on a CLI11
// subcommand and returns the function that runs it. The command line only parses arguments and
// calls the libraries; the libraries throw stm::InputError for bad input (exit code 2).
#include <CLI/CLI.hpp>
#include <functional>
#include <iostream>
#include <nlohmann/json.hpp>
#include <string>

namespace sdm_cli {

struct Command {
  CLI::App* app = nullptr;
  std::function<int()> run;
};

Command add_info_command(CLI::App& parent);
Command add_stm_command(CLI::App& parent);

// Progress lines go to stderr, so stdout stays clean for results and --json.
inline void progress(const std::string& line) { std::cerr << line << std::endl; }

inline void print_json(const nlohmann::json& j) { std::cout << j.dump(2) << std::endl; }

}  // namespace sdm_cli
