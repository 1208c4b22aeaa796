// Google Benchmark's main, plus what the project reports: for every benchmark family run at several
// sizes (BM_X/1000, BM_X/100000), the ratio of its largest to its smallest size's time (and, with
// more than two sizes, of each size to the one before), measured in the same run, so the machine's
// speed cancels out.
#include <benchmark/benchmark.h>

#include <cstdio>
#include <iterator>
#include <map>
#include <string>
#include <vector>

namespace {

class RatioReporter : public benchmark::ConsoleReporter {
 public:
  void ReportRuns(const std::vector<Run>& runs) override {
    for (const Run& run : runs) {
      // With --benchmark_repetitions the median stands for the size; without, the one run does.
      const bool median = run.run_type == Run::RT_Aggregate && run.aggregate_name == "median";
      if (run.error_occurred || !(median || run.run_type == Run::RT_Iteration) || run.run_name.args.empty()) continue;
      if (run.run_type == Run::RT_Iteration && run.repetitions > 1) continue;
      // "10000/1": the first argument is the size; the others name a variant of the family.
      const std::string& args = run.run_name.args;
      const auto slash = args.find('/');
      const std::string family = run.run_name.function_name + (slash == std::string::npos ? "" : args.substr(slash));
      try {
        families_[family][std::stol(args.substr(0, slash))] = run.GetAdjustedRealTime();
      } catch (const std::exception&) {
      }
    }
    ConsoleReporter::ReportRuns(runs);
  }

  void PrintRatios() const {
    for (const auto& [family, times] : families_) {
      if (times.size() < 2) continue;
      const auto& [small, t_small] = *times.begin();
      const auto& [large, t_large] = *times.rbegin();
      std::printf("ratio %s: time(%ld) / time(%ld) = %.2f\n", family.c_str(), large, small, t_large / t_small);
      if (times.size() < 3) continue;
      // More than two sizes: each step's growth too.
      for (auto a = times.begin(), b = std::next(a); b != times.end(); ++a, ++b) {
        std::printf("  step %s: time(%ld) / time(%ld) = %.2f\n", family.c_str(), b->first, a->first, b->second / a->second);
      }
    }
  }

 private:
  std::map<std::string, std::map<long, double>> families_;
};

}  // namespace

int main(int argc, char** argv) {
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  RatioReporter reporter;
  benchmark::RunSpecifiedBenchmarks(&reporter);
  reporter.PrintRatios();
  benchmark::Shutdown();
  return 0;
}
