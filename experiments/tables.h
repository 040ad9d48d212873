// Result tables written as CSV and Markdown with a provenance header (the
// machine, the commit, the date), through WriteFileAtomically.
//
// CSV: the header lines start with '#' (read with pandas' comment='#'), then
// one row of column names, then the rows. Empty cells mean "not applicable".

#ifndef MSDEFORM_EXPERIMENTS_TABLES_H_
#define MSDEFORM_EXPERIMENTS_TABLES_H_

#include <string>
#include <vector>

namespace msdeform {

struct Table {
  std::string title;                           // Markdown heading
  std::vector<std::string> columns;
  std::vector<std::vector<std::string>> rows;  // each as long as columns
  std::vector<std::string> notes;              // lines after the Markdown table

  void AddRow(std::vector<std::string> row);
};

// "%.4g" of a finite value; "" for NaN (not applicable); "inf"/"nan" never
// reach a table silently: they are printed as such.
std::string FormatNumber(double value, int significant = 4);
std::string FormatFixed(double value, int decimals);

// Provenance lines: machine (nproc, CPU model), the commit the binary was
// built from with msdeform's and the libraries' versions (core/build_info.h),
// and the UTC date.
std::vector<std::string> ProvenanceLines();

// Writes <out_dir>/<stem>.csv and <stem>.md. `header` lines go first in both.
bool WriteTable(const std::string& out_dir, const std::string& stem, const Table& table,
                const std::vector<std::string>& header, std::string* error);

// The parts of WriteTable, for files with more than one table:
// <out_dir>/<stem>.csv of `table` alone ('#' header lines, column names, rows);
bool WriteCsv(const std::string& out_dir, const std::string& stem, const Table& table,
              const std::vector<std::string>& header, std::string* error);
// the Markdown of one table: its title as a heading of `level` '#'s and a
// blank line (level 0: no heading), the pipe table, then its notes;
std::string MarkdownTable(const Table& table, int level);
// <out_dir>/<stem>.md: "# title", the header lines as a list, then the
// `sections` (Markdown, e.g. MarkdownTable's) separated by blank lines.
bool WriteMarkdown(const std::string& out_dir, const std::string& stem, const std::string& title,
                   const std::vector<std::string>& header, const std::vector<std::string>& sections,
                   std::string* error);

// Reads a CSV written by WriteTable (skipping '#' lines): column names and
// rows. No quoting is supported (WriteTable never writes commas in cells).
bool ReadTableCsv(const std::string& path, std::vector<std::string>* columns,
                  std::vector<std::vector<std::string>>* rows, std::string* error);

}  // namespace msdeform

#endif  // MSDEFORM_EXPERIMENTS_TABLES_H_
