// Learned models as results, through `armfarm` as a process (issue 12): a two-stage spec runs
// its stages in order (a stage that is not all done stops the later ones) and resumes; the test
// stage's jobs start from the model the train stage stored, its hash in their keys; `armfarm
// lwpr inspect|predict|export` read the stored model; a model file path works as an input file.
#include "engine/learning/learner_model_file.hpp"
#include "results/results_store.hpp"
#include "runner/execution/stored_models.hpp"

#include <gtest/gtest.h>

#include "support/scratch_file.hpp"

#include <sys/wait.h>
#include <unistd.h>

#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "support/command_line.hpp"

using armfarm::test_support::CommandResult;
using armfarm::test_support::run_armfarm;

namespace armfarm {
namespace {

namespace fs = std::filesystem;

// Train: one online job on two joints over the default sine (TRAIN_DURATION s), storing its
// model. Test: two frozen jobs starting from it, on 4 s of the sine and of a smaller one.
constexpr const char* kStagedSpec = R"({
  "name": "twostage",
  "description": "train, then test the stored model",
  "base": {"active_joints": [2, 4], "control": {"gain_scale": 0.2},
           "trajectory": {"kind": "sine", "sine": {"duration": 4}}, "learning": {"heldout": false}},
  "stages": [
    {"name": "train", "base": {"trajectory": {"sine": {"duration": TRAIN_DURATION}},
                               "learning": {"mode": "online", "store_model": true}}},
    {"name": "test", "description": "frozen",
     "base": {"learning": {"mode": "frozen", "initial_model": {"stage": "train"}}},
     "sweep": {"grid": {"trajectory.sine.amplitude": [[0.3], [0.2]]}}}
  ]
})";

class StoredModelsCli : public test_support::ScratchFolderTest {
 protected:
  StoredModelsCli() : ScratchFolderTest("models") {}
  void write_spec(const std::string& name, const std::string& duration) {
    std::string text = kStagedSpec;
    text.replace(text.find("TRAIN_DURATION"), std::string("TRAIN_DURATION").size(), duration);
    std::ofstream(path(name)) << text;
  }

  /// The train stage's job in `db`: its key and the bytes of the model it stored.
  struct TrainedModel {
    std::string key;
    std::string bytes;
  };
  static TrainedModel find_trained_model(const std::string& db) {
    const ResultsStore store = ResultsStore::open(db, ResultsStore::Mode::read_only);
    const JobRecord train = store.find_jobs("twostage.train").at(0);
    return {train.key, store.find_job_model(train.id)->data};
  }

  /// `lwpr export` of the job (by an 8-digit key prefix) writes path("m.lwpr"), byte for byte the stored model.
  void expect_export_writes_the_stored_bytes(const std::string& db, const TrainedModel& trained) {
    const CommandResult exported =
        run_armfarm("lwpr export --db " + db + " --job " + trained.key.substr(0, 8) + " -o " + path("m.lwpr"));
    ASSERT_EQ(exported.exit_code, 0) << exported.output;
    std::ifstream in(path("m.lwpr"), std::ios::binary);
    std::ostringstream file;
    file << in.rdbuf();
    EXPECT_EQ(file.str(), trained.bytes);
  }

  /// `lwpr inspect` of the file (--json) and of the job (text) describe `learner`: its sizes,
  /// updates and receptive fields.
  void expect_inspect_describes(const std::string& db, const std::string& key, const Learner& learner) {
    const CommandResult inspected = run_armfarm("lwpr inspect " + path("m.lwpr") + " --json");
    ASSERT_EQ(inspected.exit_code, 0) << inspected.output;
    const nlohmann::json info = nlohmann::json::parse(inspected.output);
    EXPECT_EQ(info["inputs"], 6);
    EXPECT_EQ(info["outputs"], 2);
    EXPECT_EQ(info["n_updates"], learner.n_updates());
    ASSERT_EQ(info["per_output"].size(), 2u);
    EXPECT_EQ(info["per_output"][0]["fields"].get<std::size_t>() + info["per_output"][1]["fields"].get<std::size_t>(), learner.size());
    EXPECT_GT(info["per_output"][0]["n_data"]["max"].get<double>(), 0.0);
    const CommandResult text = run_armfarm("lwpr inspect --db " + db + " --job " + key);
    EXPECT_EQ(text.exit_code, 0) << text.output;
    EXPECT_NE(text.output.find("lwpr model, 6 inputs -> 2 outputs"), std::string::npos) << text.output;
  }

  /// Predictions at a point of the training sine (q, q̇, q̈ of joints 2 and 4): the CLI prints the
  /// model's own prediction, to the last bit, from the file and from the database alike, and
  /// the same row from a CSV of points.
  void expect_predict_prints_the_models_prediction(const std::string& db, const std::string& key, const Learner& learner) {
    Eigen::VectorXd x(6);
    x << 0.1, 0.2, -0.3, 0.05, 0.1, -0.2;
    auto workspace = learner.make_workspace();
    const Prediction expected = learner.predict(x, *workspace);
    const std::string point = "--x 0.1,0.2,-0.3,0.05,0.1,-0.2";
    const CommandResult from_file = run_armfarm("lwpr predict " + path("m.lwpr") + " " + point);
    const CommandResult from_db = run_armfarm("lwpr predict --db " + db + " --job " + key + " " + point);
    ASSERT_EQ(from_file.exit_code, 0) << from_file.output;
    EXPECT_EQ(from_file.output, from_db.output);
    std::istringstream lines(from_file.output);
    std::string header, row;
    std::getline(lines, header);
    std::getline(lines, row);
    EXPECT_EQ(header, "x1,x2,x3,x4,x5,x6,y1,confidence1,y2,confidence2");
    std::vector<std::string> cells;
    std::stringstream cell_stream(row);
    for (std::string cell; std::getline(cell_stream, cell, ',');) cells.push_back(cell);
    ASSERT_EQ(cells.size(), 10u) << row;
    for (int o = 0; o < 2; ++o) {
      if (!expected.output_trusted[o]) continue;
      EXPECT_EQ(std::stod(cells[6 + 2 * o]), expected.value(o)) << o;
      EXPECT_EQ(std::stod(cells[7 + 2 * o]), expected.confidence(o)) << o;
    }
    std::ofstream(path("points.csv")) << "q2,q4,qd2,qd4,qdd2,qdd4\n0.1,0.2,-0.3,0.05,0.1,-0.2\n";
    const CommandResult from_csv = run_armfarm("lwpr predict " + path("m.lwpr") + " --csv " + path("points.csv"));
    ASSERT_EQ(from_csv.exit_code, 0) << from_csv.output;
    EXPECT_EQ(from_csv.output.substr(from_csv.output.find('\n')), from_file.output.substr(from_file.output.find('\n')));
  }

  /// Bad input to the verbs (a point of the wrong size, a key no job has): one line, exit 2.
  void expect_bad_verb_input_refused(const std::string& db) {
    const CommandResult wrong_size = run_armfarm("lwpr predict " + path("m.lwpr") + " --x 1,2");
    EXPECT_EQ(wrong_size.exit_code, 2);
    EXPECT_NE(wrong_size.output.find("the model has 6 inputs"), std::string::npos) << wrong_size.output;
    const CommandResult no_job = run_armfarm("lwpr inspect --db " + db + " --job ffffffff");
    EXPECT_EQ(no_job.exit_code, 2);
    EXPECT_NE(no_job.output.find("no job with that key"), std::string::npos) << no_job.output;
  }

  /// The exported file as an input file: a job starting from it (its content hash in the key)
  /// expands and runs into `db`.
  void expect_exported_file_runs_as_an_input(const std::string& db) {
    std::ofstream(path("from_file.json")) << R"({"name": "from_file", "base": {"active_joints": [2, 4],
      "trajectory": {"kind": "sine", "sine": {"duration": 2}}, "control": {"gain_scale": 0.2},
      "learning": {"mode": "frozen", "heldout": false, "initial_model": "m.lwpr"}}})";
    const CommandResult expanded = run_armfarm("expand " + path("from_file.json") + " --json");
    ASSERT_EQ(expanded.exit_code, 0) << expanded.output;
    EXPECT_NE(expanded.output.find("\"learning.initial_model\""), std::string::npos) << expanded.output;
    const CommandResult ran = run_armfarm("run " + path("from_file.json") + " --db " + db);
    EXPECT_EQ(ran.exit_code, 0) << ran.output;
  }
};

TEST_F(StoredModelsCli, TwoStagesRunInOrderFromTheStoredModelAndResume) {
  write_spec("staged.json", "4");
  const std::string db = path("staged.db");
  // The train job cannot finish within a microsecond: the test stage must not run.
  const CommandResult cut = run_armfarm("run " + path("staged.json") + " --db " + db + " -j 2 --timeout 0.000001");
  EXPECT_EQ(cut.exit_code, 1) << cut.output;
  EXPECT_NE(cut.output.find("later stages did not run"), std::string::npos) << cut.output;
  EXPECT_EQ(cut.output.find("sweep twostage.test"), std::string::npos) << cut.output;

  const CommandResult first = run_armfarm("run " + path("staged.json") + " --db " + db + " -j 2");
  ASSERT_EQ(first.exit_code, 0) << first.output;
  const std::size_t train_at = first.output.find("sweep twostage.train (stage 1 of 2)");
  const std::size_t test_at = first.output.find("sweep twostage.test (stage 2 of 2)");
  ASSERT_NE(train_at, std::string::npos) << first.output;
  ASSERT_NE(test_at, std::string::npos) << first.output;
  EXPECT_LT(train_at, test_at);

  const ResultsStore store = ResultsStore::open(db, ResultsStore::Mode::read_only);
  const std::vector<JobRecord> train = store.find_jobs("twostage.train");
  const std::vector<JobRecord> test = store.find_jobs("twostage.test");
  ASSERT_EQ(train.size(), 1u);
  ASSERT_EQ(test.size(), 2u);
  const std::optional<StoredModelRecord> model = store.find_job_model(train[0].id);
  ASSERT_TRUE(model.has_value());
  EXPECT_EQ(model->kind, "lwpr");
  EXPECT_EQ(decode_learner_model(model->data)->input_dim(), 6);
  for (const JobRecord& job : test) {
    EXPECT_EQ(job.status, "done") << job.message;
    const nlohmann::json& source = job.config["inputs"]["learning.initial_model (stored)"];
    EXPECT_EQ(source["job"], train[0].key);
    EXPECT_EQ(source["hash"], model->hash);
    EXPECT_EQ(job.config["learning"]["initial_model"], "stored:" + model->hash);
    // Frozen: each test job ends with exactly the model it started from.
    const std::optional<StoredModelRecord> after = store.find_job_model(job.id);
    if (after) {
      EXPECT_EQ(after->hash, model->hash);
    }
    EXPECT_GE(*job.started_at, *train[0].finished_at);
  }

  // Resume: everything is done, nothing runs again.
  const CommandResult again = run_armfarm("run " + path("staged.json") + " --db " + db + " -j 2");
  EXPECT_EQ(again.exit_code, 0) << again.output;
  EXPECT_NE(again.output.find("sweep twostage.train: 0 done, 0 failed, 0 diverged, 0 timed out, 1 already done"), std::string::npos)
      << again.output;
  EXPECT_NE(again.output.find("sweep twostage.test: 0 done, 0 failed, 0 diverged, 0 timed out, 2 already done"), std::string::npos)
      << again.output;

  // A different training run (only the train stage changed) stores a different model: the test
  // jobs, whose configurations differ only in the model's hash, get new keys and run again.
  write_spec("staged.json", "6");
  const CommandResult changed = run_armfarm("run " + path("staged.json") + " --db " + db + " -j 2");
  EXPECT_EQ(changed.exit_code, 0) << changed.output;
  EXPECT_NE(changed.output.find("sweep twostage.test: 2 done, 0 failed, 0 diverged, 0 timed out, 0 already done"), std::string::npos)
      << changed.output;
}

// Each step stops the test at its first fatal failure, as the one body it was did (a later step
// reads what an earlier one wrote: m.lwpr).
TEST_F(StoredModelsCli, LwprVerbsInspectPredictAndExportAStoredModel) {
  write_spec("staged.json", "4");
  const std::string db = path("verbs.db");
  const CommandResult run = run_armfarm("run " + path("staged.json") + " --db " + db + " -j 2");
  ASSERT_EQ(run.exit_code, 0) << run.output;
  const TrainedModel trained = find_trained_model(db);
  const auto learner = decode_learner_model(trained.bytes);

  ASSERT_NO_FATAL_FAILURE(expect_export_writes_the_stored_bytes(db, trained));
  ASSERT_NO_FATAL_FAILURE(expect_inspect_describes(db, trained.key, *learner));
  ASSERT_NO_FATAL_FAILURE(expect_predict_prints_the_models_prediction(db, trained.key, *learner));
  expect_bad_verb_input_refused(db);
  expect_exported_file_runs_as_an_input(db);
}

TEST_F(StoredModelsCli, BadReferencesAreOneLineErrors) {
  std::ofstream(path("bad.json")) << R"({"name": "bad", "base": {"active_joints": [2, 4],
      "learning": {"mode": "frozen", "initial_model": {"sweep": "nothing"}}}})";
  const CommandResult no_db = run_armfarm("run " + path("bad.json") + " --db " + path("none.db"));
  EXPECT_EQ(no_db.exit_code, 2);
  EXPECT_NE(no_db.output.find("bad.json: base.learning.initial_model: learning.initial_model: "), std::string::npos) << no_db.output;
  EXPECT_NE(no_db.output.find("no such database file"), std::string::npos) << no_db.output;
  EXPECT_FALSE(fs::exists(path("none.db")));

  std::ofstream(path("forward.json")) << R"({"name": "fw", "stages": [
      {"name": "a", "base": {"learning": {"initial_model": {"stage": "b"}}}}, {"name": "b"}]})";
  const CommandResult forward = run_armfarm("run " + path("forward.json") + " --db " + path("none.db"));
  EXPECT_EQ(forward.exit_code, 2);
  EXPECT_NE(forward.output.find("stages[0] (a): {\"stage\":\"b\"}: \"stage\" names an earlier stage"), std::string::npos)
      << forward.output;
}

}  // namespace
}  // namespace armfarm
