#include "experiments/tables.h"

#include <cmath>
#include <cstdio>
#include <ctime>
#include <fstream>
#include <sstream>
#include <thread>

#include <glog/logging.h>

#include "msdeform/core/atomic_file.h"
#include "msdeform/core/build_info.h"
#include "msdeform/solvers/ceres_solver.h"

namespace msdeform {
namespace {

std::string SanitiseCell(std::string cell) {
  for (char& c : cell)
    if (c == ',' || c == '\n' || c == '|') c = ';';
  return cell;
}

// The pipe table and, after a blank line, its notes.
std::string PipeTable(const Table& table) {
  std::ostringstream md;
  md << "|";
  for (const std::string& column : table.columns) md << " " << SanitiseCell(column) << " |";
  md << "\n|";
  for (size_t c = 0; c < table.columns.size(); ++c) md << "---|";
  md << "\n";
  for (const auto& row : table.rows) {
    md << "|";
    for (const std::string& cell : row) md << " " << SanitiseCell(cell) << " |";
    md << "\n";
  }
  if (!table.notes.empty()) {
    md << "\n";
    for (const std::string& note : table.notes) md << note << "\n";
  }
  return md.str();
}

bool WriteText(const std::string& path, const std::string& content, std::string* error) {
  return WriteFileAtomically(
      path,
      [&](std::ostream& out, std::string*) {
        out << content;
        return static_cast<bool>(out);
      },
      error);
}

}  // namespace

void Table::AddRow(std::vector<std::string> row) {
  CHECK_EQ(row.size(), columns.size()) << title;
  rows.push_back(std::move(row));
}

std::string FormatNumber(double value, int significant) {
  if (std::isnan(value)) return "";
  char buffer[64];
  std::snprintf(buffer, sizeof(buffer), "%.*g", significant, value);
  return buffer;
}

std::string FormatFixed(double value, int decimals) {
  if (std::isnan(value)) return "";
  char buffer[64];
  std::snprintf(buffer, sizeof(buffer), "%.*f", decimals, value);
  return buffer;
}

std::vector<std::string> ProvenanceLines() {
  return {"machine: nproc " + std::to_string(NumCores()) + ", " + CpuModel(),
          std::string("commit: ") + MsdeformCommit() + " (msdeform " + MsdeformVersion() +
              "; Ceres " + CeresVersion() + ", Eigen " + EigenVersion() + ", OpenMesh " +
              OpenMeshVersion() + ")",
          "date: " + UtcNow()};
}

bool WriteCsv(const std::string& out_dir, const std::string& stem, const Table& table,
              const std::vector<std::string>& header, std::string* error) {
  std::ostringstream csv;
  for (const std::string& line : header) csv << "# " << line << "\n";
  for (size_t c = 0; c < table.columns.size(); ++c)
    csv << (c ? "," : "") << SanitiseCell(table.columns[c]);
  csv << "\n";
  for (const auto& row : table.rows) {
    for (size_t c = 0; c < row.size(); ++c) csv << (c ? "," : "") << SanitiseCell(row[c]);
    csv << "\n";
  }
  return WriteText(out_dir + "/" + stem + ".csv", csv.str(), error);
}

std::string MarkdownTable(const Table& table, int level) {
  return (level > 0 ? std::string(level, '#') + " " + table.title + "\n\n" : std::string()) +
         PipeTable(table);
}

bool WriteMarkdown(const std::string& out_dir, const std::string& stem, const std::string& title,
                   const std::vector<std::string>& header, const std::vector<std::string>& sections,
                   std::string* error) {
  std::ostringstream md;
  md << "# " << title << "\n\n";
  for (const std::string& line : header) md << "- " << line << "\n";
  for (const std::string& section : sections) md << "\n" << section;
  return WriteText(out_dir + "/" + stem + ".md", md.str(), error);
}

bool WriteTable(const std::string& out_dir, const std::string& stem, const Table& table,
                const std::vector<std::string>& header, std::string* error) {
  return WriteCsv(out_dir, stem, table, header, error) &&
         WriteMarkdown(out_dir, stem, table.title, header, {MarkdownTable(table, 0)}, error);
}

bool ReadTableCsv(const std::string& path, std::vector<std::string>* columns,
                  std::vector<std::vector<std::string>>* rows, std::string* error) {
  std::ifstream in(path);
  if (!in) {
    *error = path + ": cannot open";
    return false;
  }
  columns->clear();
  rows->clear();
  std::string line;
  bool have_columns = false;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#') continue;
    std::vector<std::string> cells;
    std::stringstream stream(line);
    std::string cell;
    while (std::getline(stream, cell, ',')) cells.push_back(cell);
    if (!line.empty() && line.back() == ',') cells.push_back("");
    if (!have_columns) {
      *columns = cells;
      have_columns = true;
    } else {
      if (cells.size() != columns->size()) {
        *error = path + ": a row has " + std::to_string(cells.size()) + " cells, expected " +
                 std::to_string(columns->size());
        return false;
      }
      rows->push_back(cells);
    }
  }
  if (!have_columns) {
    *error = path + ": no column names";
    return false;
  }
  return true;
}

}  // namespace msdeform
