// The files of a robustness sweep, written alike by a run and by a merge of shards.
#pragma once

#include <string>
#include <vector>

#include "puppet/compare/output_folder.h"
#include "puppet/compare/robustness.h"

namespace puppet::testbed {

// robustness.csv, robustness_summary.csv and worst.csv into the folder's staging, from the rows
// in job order: the summary and the worst starts are read from the rows as written, so that a
// merge of shards, which reads them back, writes the same bytes. Returns robustness.csv's text.
std::string write_robustness(const compare::OutputFolder& folder,
                             const std::vector<compare::RobustnessRow>& rows,
                             const compare::RobustnessSpec& spec);

}  // namespace puppet::testbed
