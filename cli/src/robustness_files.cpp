#include "robustness_files.h"

#include "puppet/compare/output.h"

namespace puppet::testbed {

using namespace puppet::compare;

std::string write_robustness(const OutputFolder& folder, const std::vector<RobustnessRow>& rows,
                             const RobustnessSpec& spec) {
  const std::string csv = robustness_csv(rows);
  const std::vector<RobustnessRow> written = parse_robustness_csv(csv, "robustness.csv");
  write_file_atomically((folder.staging() / "robustness.csv").string(), csv);
  write_file_atomically((folder.staging() / "robustness_summary.csv").string(),
                        robustness_summary_csv(written));
  write_file_atomically((folder.staging() / "worst.csv").string(), worst_csv(written, spec));
  return csv;
}

}  // namespace puppet::testbed
