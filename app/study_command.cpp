// `poresph study SCENE --vary NAME=v1,v2 [--vary ...] [--set key=value] --out DIR`: the
// speed/accuracy trade of a scene over a grid of numerical settings (docs/choosing-settings.md,
// docs/cli.md). The driver is libcore/study.hpp (shared with `poresph sweep`): one folder per
// run, each run's error against the scene's `reference:` (libcore/reference.hpp) or the finest
// run, wall and CPU time, peak memory, particles, steps and health; DIR/study.csv, study.md and
// study.png (scripts/plot_study.py). A run that fails is a row.
#include <memory>

#include "app/commands.hpp"
#include "libcore/study.hpp"

namespace poresph::app {

Command addStudyCommand(CLI::App& app) {
  auto o = std::make_shared<StudyOptions>();
  CLI::App* c = app.add_subcommand(
      "study", "Error, cost and health of a scene over a grid of numerical settings");
  c->add_option("scene", o->scene, "Scene file (YAML) with a `reference:` section")->required();
  c->add_option("--vary", o->vary,
                "NAME=v1,v2,... (repeatable): spacing, kernel, h_over_dx, cfl, dt, integrator, "
                "end_time, or a scene key path with a dot (materials.gas.density)")
      ->required();
  c->add_option("--set", o->sets, "key.path=value for every run (repeatable)");
  c->add_option("--out,-o", o->out, "Study folder: one sub-folder per run, study.csv/.md/.png")->required();
  c->add_option("--threads,-t", o->threads, "OpenMP threads for each run");
  c->add_option("--cost", o->cost,
                "wall (default) or cpu: the cost axis of the Pareto front and the plot (cpu on a "
                "loaded machine)");
  c->add_flag("--overwrite", o->overwrite, "Replace the runs of an existing, non-empty study folder");
  c->add_flag("--no-plot", o->noPlot, "Do not draw study.png");
  return {c, [o] {
            const auto rows = runStudy(*o);
            int healthy = 0;
            for (const auto& r : rows) healthy += r.healthy;
            std::cout << "runs:         " << healthy << " healthy, " << rows.size() - healthy
                      << " failed or unstable (rows in study.md)\n";
            return 0;
          }};
}

}  // namespace poresph::app
