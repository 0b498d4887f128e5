#pragma once
// Sub-commands defined in their own files (app/*_command.cpp); main.cpp registers them.
#include <CLI/CLI.hpp>
#include <functional>
#include <string>

namespace poresph::app {

struct Command {
  CLI::App* sub = nullptr;
  std::function<int()> run;  ///< called after parsing when `sub` was given
};

/// `poresph image FILE ...`: statistics, pore sizes, labelled .vti (docs/voxel-images.md).
Command addImageCommand(CLI::App& app);
/// `poresph synth OUT ...`: the seeded synthetic clay-like image (data/README.md).
Command addSynthCommand(CLI::App& app);
/// `poresph sweep SCENE --set key=v1,v2 ... --out DIR`: a case-by-case study (docs/cli.md).
Command addSweepCommand(CLI::App& app);
/// `poresph study SCENE --vary name=v1,v2 ... --out DIR`: error vs cost of numerical settings.
Command addStudyCommand(CLI::App& app);

/// A whole number in [lo, hi] from an option's text; InputError naming the option and the rule.
long long wholeNumber(const std::string& option, const std::string& text, long long lo,
                      long long hi, const std::string& rule);

}  // namespace poresph::app
