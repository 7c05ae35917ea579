// mostar_record_info FILE: prints a recording's summary (header, duration, topics with counts,
// rates, sizes and gaps, damage). Exit code: 0 readable and intact, 1 readable up to damage,
// 2 missing, unreadable or refused file (wrong magic, newer format version, bad header).
#include <CLI/CLI.hpp>
#include <cstdio>
#include <iostream>

#include "common/record/recording_reader.h"
#include "common/record/recording_summary.h"

int main(int argc, char** argv) {
  CLI::App app{"Prints the summary of a mostar recording."};
  std::string path;
  double gap_s = 1.0;
  size_t max_gaps = 20;
  app.add_option("file", path, "recording file")->required();
  app.add_option("--gap-s", gap_s, "list inter-record gaps longer than this, seconds")
      ->check(CLI::PositiveNumber);
  app.add_option("--max-gaps", max_gaps, "gaps listed per topic");
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    const int code = app.exit(e);
    return code == 0 ? 0 : 2;
  }

  std::string error;
  std::unique_ptr<mostar::record::RecordingReader> reader =
      mostar::record::RecordingReader::Open(path, &error);
  if (reader == nullptr) {
    std::cerr << "mostar_record_info: " << error << "\n";
    return 2;
  }
  const mostar::record::RecordingSummary summary =
      mostar::record::SummarizeRecording(reader.get(), mostar::FromSeconds(gap_s));
  std::cout << path << "\n" << mostar::record::FormatSummary(summary, max_gaps);
  return summary.damage.has_value() ? 1 : 0;
}
