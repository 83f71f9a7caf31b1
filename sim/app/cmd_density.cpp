// `fovsim density`: analytic sampling density of a mapping method / baseline as a function of
// eccentricity along several directions from the gaze (from the map's Jacobian, see
// sim/foveation/density.h), and the theoretical shading reduction (shaded samples / W H and
// the speedup W H / shaded, Ye et al. 2022 §5.1, Fig. 11). Writes PREFIX.csv and PREFIX.json;
// --plot runs viz/plot_density.py on them.
#include <cmath>
#include <cstdlib>
#include <sstream>

#include "sim/app/commands.h"
#include "sim/core/error.h"
#include "sim/core/files.h"
#include "sim/core/text.h"
#include "sim/experiment/config.h"
#include "sim/experiment/plots.h"
#include "sim/foveation/density.h"
#include "sim/foveation/factory.h"

namespace fovsim::app {

namespace {
// Default of --max-rows: most rows `fovsim density` writes (configs/README.md "Limits on input").
constexpr double kMaxDensityRows = 2e6;
struct DensityArgs {
  std::vector<std::string> methods = methods_with_sampling_geometry();
  std::vector<std::string> params;  // METHOD.key=value
  std::string display = kDefaultDisplay, models, out = "results/density/density";
  double gaze_u = 0.5, gaze_v = 0.5, target = 0, max_rows = kMaxDensityRows;
  int directions = 8, samples = 200;
  bool plot = false;
};

int run_density(const DensityArgs& a) {
  const std::string models = a.models.empty() ? default_models_dir() : a.models;
  Display d = Display::load(a.display, models);
  Camera cam = Camera::from_pose(d, glm::dvec3(0), glm::dquat(1, 0, 0, 0));
  MappingView v = MappingView::at(cam, {a.gaze_u * d.width, a.gaze_v * d.height});
  std::vector<float> ecc = eccentricity_map(cam, v.gaze_dir);
  v.ecc = &ecc;
  const double total = double(d.width) * d.height;
  std::ostringstream csv;
  csv << "method,direction_deg,dist_px,x,y,ecc_deg,density,density_capped\n";
  Json summary = Json::object();
  summary["display"] = d.to_json();
  summary["gaze_px"] = {v.gaze_px.x, v.gaze_px.y};
  // Every --param names a selected method (a typo or an unselected method is an error, not
  // ignored) and has the form METHOD.key=value.
  for (const std::string& kv : a.params) {
    auto dot = kv.find('.'), eq = kv.find('=');
    if (dot == std::string::npos || eq == std::string::npos || eq < dot)
      throw Error("--param " + kv, "expected METHOD.key=value");
    bool selected = false;
    for (const std::string& arg : a.methods)
      selected = selected || parse_method_arg(arg, "--method").name == kv.substr(0, dot);
    if (!selected)
      throw Error("--param " + kv,
                  "method \"" + kv.substr(0, dot) + "\" is not selected with --method");
  }
  // Rows written: bounded before any is computed (about 100 bytes and one density solve each).
  const double rows = double(a.methods.size()) * a.directions * a.samples;
  if (rows > a.max_rows)
    throw Error("--samples",
                "--directions " + std::to_string(a.directions) + " x --samples " +
                    std::to_string(a.samples) + " x " + std::to_string(a.methods.size()) +
                    " methods = " + std::to_string(int64_t(rows)) + " rows, over the limit of " +
                    std::to_string(int64_t(a.max_rows)) + " (--max-rows)");
  check_output_target(a.out + ".csv");
  check_output_target(a.out + ".json");
  for (const std::string& arg : a.methods) {
    // One syntax on every command: "kfr:sigma=1.8,alpha=2" (parse_method_arg); --param
    // METHOD.key=value is kept as an alias.
    const MethodArg ma = parse_method_arg(arg, "--method");
    const std::string& m = ma.name;
    Json pj = ma.params;
    for (const std::string& kv : a.params) {  // "kfr.alpha=2"
      auto dot = kv.find('.'), eq = kv.find('=');
      if (dot == std::string::npos || eq == std::string::npos || eq < dot)
        throw Error("--param " + kv, "expected METHOD.key=value");
      if (kv.substr(0, dot) != m) continue;
      std::string val = kv.substr(eq + 1);
      const std::string key = kv.substr(dot + 1, eq - dot - 1);
      if (pj.contains(key))
        throw Error("--param " + kv, "\"" + key + "\" is also given in --method " + arg);
      pj[key] = parse_value_or_string(val, "--param " + kv);
    }
    // The method's own parser (make_method: unknown keys are errors) and its sampling geometry.
    Params p(pj, "--method " + arg, "");
    const auto inst = make_method(m, p);
    if (!inst->mapping_spec())
      throw Error(
          "--method " + arg,
          "\"" + m +
              "\" has no analytic sampling density (only image-mapping methods and baselines)");
    MappingSpec s = *inst->mapping_spec();
    bool reachable = true;
    const double target = a.target > 0 ? a.target : s.target_shaded_fraction();
    if (target > 0) {
      MappingSpec r;
      reachable = solve_iso_budget(s, v, target, r);
      s = r;
    }
    const double shaded = expected_shaded_samples(s, v);
    Json js;
    js["shaded_samples"] = shaded;
    js["shaded_fraction"] = shaded / total;
    js["theoretical_speedup"] = shaded > 0 ? total / shaded : 0.0;
    Json cols = Json::object();
    for (auto& c : s.columns()) cols[c.first] = c.second;
    js["params"] = cols;
    if (target > 0) {
      js["target_shaded_fraction"] = target;
      js["target_reachable"] = reachable;
    }
    summary["methods"][ma.text] = js;
    for (int k = 0; k < a.directions; ++k) {
      const double th = 2.0 * kPi * k / a.directions;
      const double dx = std::cos(th), dy = std::sin(th);
      // Distance to the screen border along this direction.
      double tmax = 1e30;
      if (dx > 0) tmax = std::min(tmax, (d.width - v.gaze_px.x) / dx);
      if (dx < 0) tmax = std::min(tmax, -v.gaze_px.x / dx);
      if (dy > 0) tmax = std::min(tmax, (d.height - v.gaze_px.y) / dy);
      if (dy < 0) tmax = std::min(tmax, -v.gaze_px.y / dy);
      if (!(tmax > 0)) continue;
      for (int i = 0; i < a.samples; ++i) {
        const double t = tmax * (i + 0.5) / a.samples;
        const double x = v.gaze_px.x + dx * t, y = v.gaze_px.y + dy * t;
        const double dens = sample_density(s, v, x, y);
        csv << ma.text << ',' << rad2deg(th) << ',' << t << ',' << x << ',' << y << ','
            << v.ecc_deg(x, y) << ',' << dens << ',' << std::min(dens, 1.0) << '\n';
      }
    }
  }
  write_file_atomic(a.out + ".csv", csv.str());
  write_file_atomic(a.out + ".json", summary.dump(2) + "\n");
  for (auto& [m, js] : summary["methods"].items())
    std::printf("%-11s shaded_fraction %.4f  theoretical speedup %.2fx\n", m.c_str(),
                js["shaded_fraction"].get<double>(), js["theoretical_speedup"].get<double>());
  std::printf("wrote %s.csv, %s.json\n", a.out.c_str(), a.out.c_str());
  if (a.plot) {  // the one launcher (sim/experiment/plots.h): finds viz/ from any directory
    PlotOutcome p = run_plot_script("plot_density.py", {a.out + ".csv", a.out + ".png"}, false);
    if (p.status == PlotOutcome::Status::Failed) throw Error("--plot", p.message);
    if (!p.message.empty()) std::printf("%s\n", p.message.c_str());
  }
  return 0;
}
}  // namespace

void register_density(CLI::App& app, Action& action) {
  auto a = std::make_shared<DensityArgs>();
  CLI::App* c = app.add_subcommand(
      "density", "Analytic sampling density and theoretical shading reduction of mapping methods");
  c->add_option(
       "--method,-m", a->methods,
       "Method and parameters in the syntax of every command, e.g. kfr, "
       "kfr:sigma=1.8,alpha=2, rmfr:fx=0.3 "
       "(keys as in the run config; repeat); one of the methods with a sampling geometry: " +
           join_names(methods_with_sampling_geometry()))
      ->capture_default_str();
  c->add_option("--param", a->params, "Alias: METHOD.key=value, e.g. kfr.alpha=2 (repeat)");
  c->add_option("--display", a->display, "Display name or path (models/displays/NAME.json)")
      ->capture_default_str();
  c->add_option("--models", a->models, "Models directory");
  add_number(c, "--gaze-u", a->gaze_u, "Gaze x as a fraction of W",
             {Range::closed(0, 1), "fraction"})
      ->capture_default_str();
  add_number(c, "--gaze-v", a->gaze_v, "Gaze y as a fraction of H",
             {Range::closed(0, 1), "fraction"})
      ->capture_default_str();
  add_number(c, "--target", a->target,
             "Iso-budget: shaded fraction every method is tuned to (Ye et al. 2022 §5.1)",
             {Range::above(0, 1), "fraction"});
  add_number(c, "--directions", a->directions, "Directions from the gaze",
             {Range::closed(1, 360), "directions"})
      ->capture_default_str();
  add_number(c, "--samples", a->samples, "Samples per direction",
             {Range::closed(1, 100000), "samples"})
      ->capture_default_str();
  add_number(c, "--max-rows", a->max_rows,
             "Most rows (methods x --directions x --samples), checked before any is computed",
             {Range::closed(1, 1e9), "rows"})
      ->capture_default_str();
  c->add_option("--out", a->out, "Output prefix (writes PREFIX.csv, PREFIX.json)")
      ->capture_default_str();
  c->add_flag("--plot", a->plot, "Plot with viz/plot_density.py (PREFIX.png)");
  c->callback([a, &action] { action = [a] { return run_density(*a); }; });
}

}  // namespace fovsim::app
