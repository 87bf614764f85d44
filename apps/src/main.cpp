// The planemap command-line tool: thin wiring of the library's modules.
#include <cstdio>
#include <exception>
#include <limits>

#include <CLI/CLI.hpp>
#include <spdlog/sinks/stdout_color_sinks.h>
#include <spdlog/spdlog.h>

#include "planemap/apps/commands.h"

namespace {
// Integer options' ranges, checked as the command line is read.
const CLI::Range kCount(0, std::numeric_limits<int>::max());       // seeds, indices, 0 = every core
const CLI::Range kCountOfOne(1, std::numeric_limits<int>::max());  // frames, runs, strides
}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"planemap: plane-based object maps, poses and grasp approach from RGB-D"};
  app.require_subcommand(1);
  bool verbose = false;
  app.add_flag("-v,--verbose", verbose, "Log progress details");

  planemap::RenderOptions render;
  CLI::App* render_cmd = app.add_subcommand(
      "render", "Render a simulated RGB-D sequence (TUM layout, labels, ground truth) of a scene along a walk");
  render_cmd->add_option("--scene", render.scene, "Scene description (YAML)")->capture_default_str();
  render_cmd->add_option("--trajectory", render.trajectory, "Walk description (.yaml) or TUM trajectory file")
      ->capture_default_str();
  render_cmd->add_option("--camera", render.camera, "Camera intrinsics (YAML)")->capture_default_str();
  render_cmd->add_option("--config", render.config, "Settings (YAML), see configs/default.yaml")->capture_default_str();
  render_cmd->add_option("--out", render.out, "Output folder")->capture_default_str();
  render_cmd->add_option("--max-frames", render.max_frames, "Render only the first N poses")->check(kCountOfOne);
  render_cmd->add_option("--seed", render.seed, "Noise seed (overrides render.seed)")->check(kCount);
  render_cmd->add_flag("--exact", render.exact, "No sensor noise: exact depth");

  planemap::InspectOptions inspect;
  CLI::App* inspect_cmd = app.add_subcommand("inspect", "Read a TUM-layout RGB-D sequence and report what it holds");
  inspect_cmd->add_option("sequence", inspect.sequence, "Sequence folder (rgb.txt, depth.txt, ...)")->required();
  inspect_cmd->add_option("--camera", inspect.camera,
                          "Camera intrinsics (YAML); default: the sequence's camera.yaml, else "
                          "configs/cameras/tum_openni_default.yaml");
  inspect_cmd->add_option("--config", inspect.config, "Settings (YAML)")->capture_default_str();
  inspect_cmd->add_option("--max-frames", inspect.max_frames, "Read only the first N frames")->check(kCountOfOne);

  planemap::FrameOptions frame;
  CLI::App* frame_cmd = app.add_subcommand(
      "frame", "Planes, intersections, trihedral angles and classified objects of one RGB-D frame; prints JSON");
  frame_cmd->add_option("--sequence", frame.sequence, "TUM-layout sequence folder");
  frame_cmd->add_option("--index", frame.index, "Frame index in the sequence")->capture_default_str()->check(kCount);
  frame_cmd->add_option("--depth", frame.depth, "Depth PNG (16-bit, camera depth_scale units per metre)");
  frame_cmd->add_option("--color", frame.color, "Colour PNG matching --depth");
  frame_cmd->add_option("--pcd", frame.pcd, "Organized PCD point cloud (metres, camera frame)");
  frame_cmd->add_option("--camera", frame.camera,
                        "Camera intrinsics (YAML); default: the sequence's camera.yaml, else "
                        "configs/cameras/tum_openni_default.yaml");
  frame_cmd->add_option("--config", frame.config, "Settings (YAML)")->capture_default_str();
  frame_cmd->add_option("--patterns", frame.patterns, "Object graph patterns (YAML)")->capture_default_str();
  frame_cmd->add_option("--out", frame.out, "Output folder for model.json, model.ply, overlay.png")->capture_default_str();

  planemap::MapOptions map;
  CLI::App* map_cmd = app.add_subcommand(
      "map", "Track a TUM-layout sequence against a plane map; writes trajectory.txt, trajectory_smoothed.txt (sliding "
             "window), tracking.csv, map.json, map.ply");
  map_cmd->add_option("sequence", map.sequence, "Sequence folder (rgb.txt, depth.txt, ...)")->required();
  map_cmd->add_option("--camera", map.camera,
                      "Camera intrinsics (YAML); default: the sequence's camera.yaml, else "
                      "configs/cameras/tum_openni_default.yaml");
  map_cmd->add_option("--config", map.config, "Settings (YAML)")->capture_default_str();
  map_cmd->add_option("--patterns", map.patterns, "Object graph patterns (YAML)")->capture_default_str();
  map_cmd->add_option("--out", map.out, "Output folder")->capture_default_str();
  map_cmd->add_option("--anchor", map.anchor,
                      "World frame: groundtruth (the first frame's true pose), first (the first camera frame) or "
                      "auto (ground truth when the sequence has it)")
      ->capture_default_str();
  map_cmd->add_option("--max-frames", map.max_frames, "Use only the first N frames")->check(kCountOfOne);
  map_cmd->add_option("--stride", map.stride, "Use every n-th frame")->capture_default_str()->check(kCountOfOne);
  map_cmd->add_flag("--refine", map.refine,
                    "Refine poses, planes and boxes jointly with the Ceres back end (batch) after tracking; writes "
                    "trajectory_refined.txt and a map.json with each box's standard deviations");
  map_cmd->add_option("--report", map.report, "Write the run as a self-contained HTML page: 3-D map, trajectories, objects");

  planemap::ConsistencyOptions nees;
  CLI::App* nees_cmd = app.add_subcommand(
      "nees", "Are the back end's box-size covariances honest? Seeded renderings of a walk, each tracked and refined: "
              "the boxes' dimension errors against their covariances (NEES) and the 95% chi-square interval");
  nees_cmd->add_option("--scene", nees.scene, "Scene (YAML)")->capture_default_str();
  nees_cmd->add_option("--trajectory", nees.trajectory, "Walk (YAML) or TUM trajectory")->capture_default_str();
  nees_cmd->add_option("--camera", nees.camera, "Camera intrinsics (YAML)")->capture_default_str();
  nees_cmd->add_option("--config", nees.config, "Settings (YAML)")->capture_default_str();
  nees_cmd->add_option("--patterns", nees.patterns, "Object graph patterns (YAML)")->capture_default_str();
  nees_cmd->add_option("--runs", nees.runs, "Seeded runs")->capture_default_str()->check(kCountOfOne);
  nees_cmd->add_option("--seed", nees.first_seed, "Seed of the first run (run k: seed + k)")->capture_default_str()->check(kCount);
  nees_cmd->add_option("--stride", nees.stride, "Use every n-th pose of the walk")->capture_default_str()->check(kCountOfOne);
  nees_cmd->add_option("--threads", nees.threads, "Runs in parallel (0: every core)")->capture_default_str()->check(kCount);
  nees_cmd->add_option("--csv", nees.csv, "Write every run's errors, standard deviations and NEES here");

  planemap::ApproachCommandOptions approach;
  CLI::App* approach_cmd = app.add_subcommand(
      "approach", "The humanoid walks to the pre-grasp pose in front of the box, closed loop: rendered frames, the product's "
                  "perception and estimation, the paper's scenarios (1 open loop, 2 path feedback, 3 then object approach)");
  approach_cmd->add_option("--scene", approach.run.scene, "Scene (YAML)")->capture_default_str();
  approach_cmd->add_option("--scenario", approach.run.scenario, "1, 2 or 3")->capture_default_str();
  approach_cmd->add_option("--seed", approach.run.seed, "Walking and sensor noise seed (with --table: the first)")->capture_default_str()->check(kCount);
  approach_cmd->add_option("--camera", approach.run.camera, "Camera intrinsics (YAML)")->capture_default_str();
  approach_cmd->add_option("--config", approach.run.config, "Settings (YAML): humanoid, planner, grasp, mission")->capture_default_str();
  approach_cmd->add_option("--patterns", approach.run.patterns, "Object graph patterns (YAML)")->capture_default_str();
  approach_cmd->add_option("--target", approach.run.target, "Class of the object to approach")->capture_default_str();
  approach_cmd->add_option("--target-size", approach.run.target_size,
                           "Size of the object to approach: its two horizontal extents and height [m] (default: the "
                           "scene's task object's, else any size)")
      ->expected(3);
  approach_cmd->add_option("--start", approach.run.start, "Start pose: x y [m] heading [deg]")->expected(3);
  approach_cmd->add_option("--rate", approach.run.rate, "Camera frame rate [Hz]")->capture_default_str();
  approach_cmd->add_option("--move-object-at", approach.run.move_object_at, "Move the target in the scene at this time [s]");
  approach_cmd->add_option("--move-by", approach.run.move_object_by, "... by dx dy [m] dyaw [deg]")->expected(3);
  approach_cmd->add_option("--drop-at", approach.run.drop_at, "Lose the camera frames from this time [s] ...");
  approach_cmd->add_option("--drop-for", approach.run.drop_duration, "... for this long [s]")->capture_default_str();
  approach_cmd->add_option("--max-time", approach.run.max_time, "End the run after this long [s]")->capture_default_str();
  approach_cmd->add_flag("--table", approach.table, "All three scenarios over --seeds seeds: the paper's Table 1");
  approach_cmd->add_option("--seeds", approach.seeds, "Seeds per scenario with --table")->capture_default_str()->check(kCountOfOne);
  approach_cmd->add_option("--threads", approach.threads, "Runs in parallel with --table (0: every core)")->capture_default_str()->check(kCount);
  approach_cmd->add_option("--json", approach.json, "Write the table as JSON here (with --table)");
  approach_cmd->add_option("--plots", approach.plots, "Write Fig. 8-like SVG plots with this path prefix");
  approach_cmd->add_option("--report", approach.report,
                           "Write the run as a self-contained HTML page: 3-D map, paths, footsteps, control points, plots");
  approach_cmd->add_option("--map", approach.map, "Write the run's final map here (map.json format)");
  approach_cmd->add_option("--trace", approach.trace,
                           "Write every camera frame as CSV here: tracking status and counts, the tracked and smoothed "
                           "base pose against the truth (with --table: every run, by scenario and seed)");

  planemap::RoomsOptions rooms;
  rooms.run.rate = 15.0;
  CLI::App* rooms_cmd = app.add_subcommand(
      "rooms", "The approach over generated rooms (or given scene files): per room and seed, reached, grasp check, "
               "collision, pre-grasp error, time and the failure's reason, into a resumable CSV; a summary tallies the "
               "failures by reason");
  rooms_cmd->add_option("--count", rooms.count, "Rooms to generate")->capture_default_str()->check(kCountOfOne);
  rooms_cmd->add_option("--room-seed", rooms.room_seed, "The generator's seed")->capture_default_str()->check(kCount);
  rooms_cmd->add_option("--generator", rooms.generator, "The generator's ranges (YAML)")->capture_default_str();
  rooms_cmd->add_option("--scenes", rooms.scenes, "Run these scene files (YAML) instead of generated rooms");
  rooms_cmd->add_option("--scenario", rooms.run.scenario, "1, 2 or 3")->capture_default_str();
  rooms_cmd->add_option("--seed", rooms.run.seed, "Walking and sensor noise seed of a room's first run")->capture_default_str()->check(kCount);
  rooms_cmd->add_option("--seeds", rooms.seeds, "Runs per room")->capture_default_str()->check(kCountOfOne);
  rooms_cmd->add_option("--rate", rooms.run.rate, "Camera frame rate [Hz]")->capture_default_str();
  rooms_cmd->add_option("--max-time", rooms.run.max_time, "End a run after this long [s]")->capture_default_str();
  rooms_cmd->add_option("--camera", rooms.run.camera, "Camera intrinsics (YAML)")->capture_default_str();
  rooms_cmd->add_option("--config", rooms.run.config, "Settings (YAML)")->capture_default_str();
  rooms_cmd->add_option("--patterns", rooms.run.patterns, "Object graph patterns (YAML)")->capture_default_str();
  rooms_cmd->add_option("--out", rooms.out, "Output folder (default: out/rooms_<room seed>)");
  rooms_cmd->add_option("--threads", rooms.threads, "Runs in parallel (0: every core)")->capture_default_str()->check(kCount);
  rooms_cmd->add_option("--max-runs", rooms.max_runs, "Stop after this many new runs (0: all); run again to go on")
      ->capture_default_str()
      ->check(kCount);
  rooms_cmd->add_flag("--restart", rooms.restart, "Discard the output folder's finished runs");
  rooms_cmd->add_flag("--generate-only", rooms.generate_only, "Write the rooms' scene files and run nothing");

  planemap::StudyOptions study;
  CLI::App* study_cmd = app.add_subcommand(
      "study", "Accuracy study: a sweep of rendered runs (distance, viewing angle, noise, object size, segmenter) into a "
               "resumable CSV, a summary table (median, 90th percentile) and plots");
  study_cmd->add_option("study", study.study, "Study file (YAML), e.g. configs/studies/default.yaml")->required();
  study_cmd->add_option("--out", study.out, "Output folder (default: out/study_<name>)");
  study_cmd->add_option("--threads", study.threads, "Runs in parallel (0: every core)")->capture_default_str()->check(kCount);
  study_cmd->add_option("--max-runs", study.max_runs, "Stop after this many new runs (0: all); run again to go on")
      ->capture_default_str()
      ->check(kCount);
  study_cmd->add_flag("--restart", study.restart, "Discard the output folder's finished runs");
  study_cmd->add_option("--report", study.report,
                        "Write the study as a self-contained HTML page: summary, plots and the first run's map in 3-D");
  study_cmd->add_option("--shard", study.shard,
                        "Run only shard K of N (K/N, 1 <= K <= N; the runs dealt as in a draft: 1..N, N..1, ...) into "
                        "OUT/shards/K-of-N, resumable; one task of a cluster's job array (scripts/slurm/)");
  study_cmd->add_flag("--collect", study.collect,
                      "Merge the finished shards in OUT/shards into runs.csv, summary.csv and plots (and --report), as "
                      "the study run on one machine writes them; names a missing shard and the runs it lacks");

  planemap::EvalOptions eval;
  CLI::App* eval_cmd = app.add_subcommand(
      "eval", "Trajectory error (ATE, RPE) against ground truth; with --map and --scene, the map's object errors");
  eval_cmd->add_option("--groundtruth", eval.groundtruth, "Ground-truth trajectory (TUM format)")->required();
  eval_cmd->add_option("--estimate", eval.estimate, "Estimated trajectory (TUM format)")->required();
  eval_cmd->add_option("--map", eval.map, "Map file (map.json of planemap map)");
  eval_cmd->add_option("--scene", eval.scene, "Scene (YAML) or rendered sequence folder holding the true objects");
  eval_cmd->add_option("--config", eval.config, "Settings (YAML), see eval: in configs/default.yaml")->capture_default_str();
  eval_cmd->add_option("--csv", eval.csv, "Write every figure to this CSV file (kind,name,metric,value,unit)");
  eval_cmd->add_option("--study-csv", eval.study_csv,
                       "Write the figures as rows of a study's runs.csv (planemap study) and print its summary table");
  eval_cmd->add_option("--stage", eval.stage, "The estimate's stage in those rows: tracking or backend")->capture_default_str();

  planemap::MergeOptions merge;
  CLI::App* merge_cmd = app.add_subcommand(
      "merge", "Merge two maps (map.json of planemap map): align by plane correspondences and ICP, fuse, rebuild objects");
  merge_cmd->add_option("target", merge.target, "Map to merge into (its world frame is kept)")->required();
  merge_cmd->add_option("source", merge.source, "Map merged into it")->required();
  merge_cmd->add_option("--guess", merge.guess, "Source world in the target's: x y z [m] roll pitch yaw [deg]")->expected(6);
  merge_cmd->add_option("--config", merge.config, "Settings (YAML), see merge: in configs/default.yaml")->capture_default_str();
  merge_cmd->add_option("--patterns", merge.patterns, "Object graph patterns (YAML)")->capture_default_str();
  merge_cmd->add_option("--out", merge.out, "Output folder")->capture_default_str();

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    // --help prints and exits 0; a bad command line exits 1 like every other error (CLI11's own
    // codes, 100 and up, mean nothing to a script).
    return app.exit(e) == 0 ? 0 : 1;
  }
  // Progress and log lines go to stderr; stdout carries only the command's results.
  spdlog::set_default_logger(spdlog::stderr_color_mt("planemap"));
  spdlog::set_level(verbose ? spdlog::level::debug : spdlog::level::info);
  spdlog::set_pattern("[%H:%M:%S] %v");

  const char* command = app.get_subcommands().front()->get_name().c_str();
  try {
    if (render_cmd->parsed()) return planemap::RunRender(render);
    if (inspect_cmd->parsed()) return planemap::RunInspect(inspect);
    if (frame_cmd->parsed()) return planemap::RunFrame(frame);
    if (eval_cmd->parsed()) return planemap::RunEval(eval);
    if (map_cmd->parsed()) return planemap::RunMap(map);
    if (nees_cmd->parsed()) return planemap::RunNees(nees);
    if (merge_cmd->parsed()) return planemap::RunMerge(merge);
    if (approach_cmd->parsed()) return planemap::RunApproach(approach);
    if (study_cmd->parsed()) return planemap::RunStudy(study);
    if (rooms_cmd->parsed()) return planemap::RunRooms(rooms);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "planemap %s: error: %s\n", command, e.what());
    return 1;
  }
  return 2;
}
