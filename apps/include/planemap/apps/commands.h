#pragma once
// The planemap subcommands. Each takes its options and returns the process exit code; bad input
// throws InputError, which main() prints as one line.
#include <string>
#include <vector>

#include "planemap/apps/approach.h"
#include "planemap/apps/consistency.h"

namespace planemap {

struct RenderOptions {
  std::string scene = "configs/scenes/default.yaml";
  std::string trajectory = "configs/walks/default.yaml";
  std::string camera = "configs/cameras/xtion_nao.yaml";
  std::string config = "configs/default.yaml";
  std::string out = "out/default_walk";
  int max_frames = -1;  // < 0: all
  int seed = -1;        // < 0: the config's
  bool exact = false;   // no sensor noise
};

struct InspectOptions {
  std::string sequence;
  std::string camera;  // empty: the sequence's camera.yaml, else the TUM/OpenNI default
  std::string config = "configs/default.yaml";
  int max_frames = -1;
};

struct FrameOptions {
  std::string sequence;  // a TUM-layout folder ...
  int index = 0;         // ... and the frame in it
  std::string depth;     // or a depth PNG (and optional colour PNG)
  std::string color;
  std::string pcd;       // or an organized PCD cloud (camera frame, metres)
  std::string camera;    // empty: the sequence's camera.yaml, else the TUM/OpenNI default
  std::string config = "configs/default.yaml";
  std::string patterns = "configs/patterns.yaml";
  std::string out = "out/frame";  // overlay.png, model.ply, model.json
};

struct MapOptions {
  std::string sequence;  // a TUM-layout folder (real or rendered)
  std::string camera;    // empty: the sequence's camera.yaml, else the TUM/OpenNI default
  std::string config = "configs/default.yaml";
  std::string patterns = "configs/patterns.yaml";
  std::string out = "out/map";  // trajectory.txt, tracking.csv, map.json, map.ply
  std::string anchor = "auto";  // first pose: groundtruth | first (identity) | auto (ground truth if any)
  int max_frames = -1;          // < 0: all
  int stride = 1;               // use every n-th frame
  bool refine = false;          // batch back end after tracking: trajectory_refined.txt, map.json refined
  std::string report;           // the run as a self-contained HTML page; empty: none
};

struct EvalOptions {
  std::string groundtruth;  // TUM trajectory files
  std::string estimate;
  std::string map;          // map.json of `planemap map` (optional, with scene)
  std::string scene;        // scene YAML or a rendered sequence folder (its scene.yaml)
  std::string config = "configs/default.yaml";
  std::string csv;          // empty: no CSV
  std::string study_csv;    // the same figures as rows of a study's runs.csv; empty: none
  std::string stage = "tracking";  // the estimate's stage in those rows: tracking | backend
};

struct MergeOptions {
  std::string target;   // map.json of the map the other is merged into (its world is kept)
  std::string source;   // map.json merged into it
  std::vector<double> guess;  // the source world's pose in the target's: x y z [m] roll pitch yaw [deg]; empty: identity
  std::string config = "configs/default.yaml";
  std::string patterns = "configs/patterns.yaml";
  std::string out = "out/merged";  // map.json, map.ply
};

struct StudyOptions {
  std::string study;     // a study file (configs/studies/*.yaml)
  std::string out;       // output folder; empty: out/study_<name>
  int threads = 0;       // runs in parallel (0: every core)
  int max_runs = 0;      // stop after this many new runs (0: all); run again to go on
  bool restart = false;  // discard the folder's finished runs
  std::string report;    // the study as an HTML page (summary, plots, the first run's map); empty: none
  std::string shard;     // "K/N": run only shard K of N (apps/study.h), into out/shards/K-of-N; empty: all
  bool collect = false;  // merge the finished shards in out/shards into the whole study's files
};

struct ApproachCommandOptions {
  ApproachOptions run;
  bool table = false;   // all three scenarios over `seeds` seeds: the paper's Table 1
  int seeds = 20;
  int threads = 0;      // runs in parallel (0: every core)
  std::string json;     // the table as JSON; empty: none
  std::string plots;    // Fig. 8 as SVG files with this path prefix; empty: none
  std::string report;   // a single run as a self-contained HTML page; empty: none
  std::string map;      // a single run's final map as map.json; empty: none
  std::string trace;    // every frame of every run as CSV (pose estimate against the truth); empty: none
};

// planemap rooms: the approach over generated rooms (apps/rooms.h), or over given scene files.
struct RoomsOptions {
  ApproachOptions run;                 // scenario, first seed, rate, settings; the scene is each room's
  int count = 100;                     // rooms generated
  int room_seed = 1;                   // the generator's seed
  std::string generator = "configs/rooms/default.yaml";  // the generator's ranges
  std::vector<std::string> scenes;     // run these scene files instead of generated rooms
  int seeds = 1;                       // approach runs per room: seeds run.seed, run.seed + 1, ...
  std::string out;                     // output folder; empty: out/rooms_<room_seed>
  int threads = 0;                     // runs in parallel (0: every core)
  int max_runs = 0;                    // stop after this many new runs (0: all); run again to go on
  bool restart = false;                // discard the folder's finished runs
  bool generate_only = false;          // write the rooms, run nothing
};

int RunApproach(const ApproachCommandOptions& options);
int RunRooms(const RoomsOptions& options);
int RunMerge(const MergeOptions& options);
int RunRender(const RenderOptions& options);
int RunMap(const MapOptions& options);
int RunFrame(const FrameOptions& options);
int RunInspect(const InspectOptions& options);
int RunEval(const EvalOptions& options);
int RunNees(const ConsistencyOptions& options);
int RunStudy(const StudyOptions& options);

}  // namespace planemap
