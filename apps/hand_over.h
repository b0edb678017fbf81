#pragma once
// The `sdm` program is two: `sdm` itself runs the commands that need only libstm's core (reading,
// checking and remeshing meshes, skeletons, layouts) and hands every other command line to
// `sdm-full`, which has them all. The light commands then start without loading OpenEXR,
// OpenSubdiv and GL, about 3 ms of every start (docs/BENCHMARKS.md, "Starting fast"); the others
// pay one more exec (under 1 ms) on runs of a second or more.
#include <filesystem>
#include <string>
#include <vector>

namespace sdm::cli {

// Whether argv names, as its first argument, one of `commands` (those this program was built
// with) or --version. --help, nothing and unknown words are not: sdm-full answers them with the
// whole list of commands.
bool runs_here(const std::vector<std::string>& commands, int argc, char** argv);

// Replaces this process with sdm-full and the same arguments: beside this program (the build
// tree) or in SDM_FULL_RELATIVE from its folder (the installed tree, libexec/sdm). Returns only
// when it cannot (1, with a message naming where it looked).
int hand_over(char** argv);

// The `sdm` program users run: this one, or, from sdm-full, the `sdm` beside it (the build tree)
// or in SDM_FRONT_RELATIVE from its folder (bin, from libexec/sdm); sdm-full itself when neither is.
std::filesystem::path front_program(const char* argv0);

// `sdm batch ARGS`: replaces this process with Python running sdm_batch.py (python/sdm_batch.py:
// models as tasks on Dask) with `--sdm THIS_PROGRAM ARGS`: the script beside this program
// (python/, the build tree) or in SDM_BATCH_RELATIVE from its folder (share/sdm). The system
// interpreter (/usr/bin/python3, whose Dask Debian installs) when there is one, else python3 on
// PATH. Returns only when it cannot (1, with a message).
int hand_over_to_batch(int argc, char** argv);

}  // namespace sdm::cli
