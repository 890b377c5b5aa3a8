// Tests for src/io: atomic writes, CSV tables, run-folder markers.
#include <gtest/gtest.h>

#include <tuple>

#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <random>
#include <string>
#include <utility>

#include <unistd.h>

#include "common/errors.hpp"
#include "io/atomic_write.hpp"
#include "common/text.hpp"
#include "io/csv.hpp"
#include "io/folder_lock.hpp"
#include "io/hash.hpp"
#include "io/run_folder.hpp"
#include "io/staging.hpp"
#include "temp_dir.hpp"

namespace fs = std::filesystem;
using namespace millwear;
using millwear::testing::TempDir;

namespace {


int count_entries(const std::string& dir) {
  int n = 0;
  for (const auto& e : fs::directory_iterator(dir)) {
    (void)e;
    ++n;
  }
  return n;
}

}  // namespace

// ---- atomic writes ----

TEST(IoRunFolder, AStageFileNameGivesItsStageAndNothingElseDoes) {
  EXPECT_EQ(io::stage_in_file_name("sag-2x30_stage0.csv", "sag-2x30", ".csv"), 0);
  EXPECT_EQ(io::stage_in_file_name("sag-2x30_stage12.done", "sag-2x30", ".done"), 12);
  EXPECT_EQ(io::stage_in_file_name("sag-2x30_stage12.done", "sag-2x30", ".csv"), -1);    // another suffix
  EXPECT_EQ(io::stage_in_file_name("sag-2x30_stage12.done", "sag-1x30", ".done"), -1);   // another design
  EXPECT_EQ(io::stage_in_file_name("sag-2x30_stage.csv", "sag-2x30", ".csv"), -1);       // no number
  EXPECT_EQ(io::stage_in_file_name("sag-2x30_stage-1.csv", "sag-2x30", ".csv"), -1);     // not digits
  EXPECT_EQ(io::stage_in_file_name("sag-2x30_stage1x.csv", "sag-2x30", ".csv"), -1);
  EXPECT_EQ(io::stage_in_file_name("sag-2x30_stage1234567890.csv", "sag-2x30", ".csv"), -1);  // too long
}

// A manifest lists its files relative to OUT however OUT was typed: "out/" (as a shell's
// completion gives it) makes the writers' paths "out//x.csv", still inside.
TEST(IoRunFolder, APathUnderTheFolderIsRelativeToItHoweverTheFolderIsTyped) {
  EXPECT_EQ(io::relative_to("out", "out/profiles/a.csv"), "profiles/a.csv");
  EXPECT_EQ(io::relative_to("out/", "out//rule1.csv"), "rule1.csv");
  EXPECT_EQ(io::relative_to("./out", "out/plots/x.png"), "plots/x.png");
  EXPECT_EQ(io::relative_to("/tmp/run/", "/tmp/run/plots/x.svg"), "plots/x.svg");
  // Outside OUT, OUT itself, or no folder: nothing.
  EXPECT_EQ(io::relative_to("out", "rule1.csv"), "");
  EXPECT_EQ(io::relative_to("out", "out"), "");
  EXPECT_EQ(io::relative_to("out", "out2/x.csv"), "");
  EXPECT_EQ(io::relative_to("out", "out/../x.csv"), "");
  EXPECT_EQ(io::relative_to("", "x.csv"), "");
}

TEST(IoAtomicWrite, ReplacesContentAndLeavesNoTempFile) {
  TempDir dir{"millwear-io"};
  const std::string f = dir / "summary.csv";
  io::write_file_atomic(f, "first\n");
  EXPECT_EQ(io::read_file(f), "first\n");
  io::write_file_atomic(f, "second, longer content\n");
  EXPECT_EQ(io::read_file(f), "second, longer content\n");
  EXPECT_EQ(count_entries(dir.path()), 1);  // only the target, no .tmp.<pid> left behind
}

TEST(IoAtomicWrite, FailureIsRunErrorNamingThePath) {
  TempDir dir{"millwear-io"};
  const std::string f = dir / "no/such/folder/x.csv";
  try {
    io::write_file_atomic(f, "x");
    FAIL() << "expected RunError";
  } catch (const RunError& e) {
    EXPECT_NE(std::string(e.what()).find(f), std::string::npos) << e.what();
  }
}

TEST(IoAtomicWrite, EnsureDirCreatesNestedFoldersAndIsIdempotent) {
  TempDir dir{"millwear-io"};
  const std::string d = dir / "a/b/c";
  io::ensure_dir(d);
  io::ensure_dir(d);
  EXPECT_TRUE(fs::is_directory(d));
  io::write_file_atomic(dir / "file", "x");
  EXPECT_THROW(io::ensure_dir(dir / "file"), RunError);
}

TEST(IoAtomicWrite, TemporariesAreHiddenAndTaggedNextToTheTarget) {
  const std::string t = io::temp_path_for("out/profiles/a_stage1.csv");
  const std::string prefix = "out/profiles/.a_stage1.csv.millwear-tmp." + std::to_string(::getpid()) + ".";
  EXPECT_EQ(t.compare(0, prefix.size(), prefix), 0) << t;
  EXPECT_TRUE(io::is_temp_name(fs::path(t).filename().string())) << t;
  EXPECT_TRUE(io::is_temp_name(".fig7_area.millwear-tmp.12.3.png"));  // a figure's temporary base
  // Names a user (or another program) may well write are never taken for ours.
  for (const char* name : {"x.tmp.1", "leftover.csv.tmp.1234.0", "keep.tmp.csv", ".x.millwear-tmp.",
                           "x.millwear-tmp.1.2", ".x.millwear-tmp.1", ".x.millwear-tmp.1.2x", ".millwear-tmp.1.2"})
    EXPECT_FALSE(io::is_temp_name(name)) << name;
}

TEST(IoAtomicWrite, RemoveStaleTempsDeletesOnlyTemporaries) {
  TempDir dir{"millwear-io"};
  io::write_file_atomic(dir / "keep.csv", "x");
  io::write_file_atomic(dir / "keep.tmp.csv", "x");             // ".tmp." not followed by a pid
  io::write_file_atomic(dir / "x.tmp.1", "a user's file");      // a pattern of temporaries not ours
  io::write_file_atomic(dir / "notes.csv.tmp.1234.0", "a user's file");
  io::write_file_atomic(dir / ".leftover.csv.millwear-tmp.1234.0", "x");
  io::write_file_atomic(dir / ".fig.millwear-tmp.1234.1.png", "x");
  EXPECT_EQ(io::remove_stale_temps(dir.path()), 2);
  for (const char* kept : {"keep.csv", "keep.tmp.csv", "x.tmp.1", "notes.csv.tmp.1234.0"})
    EXPECT_TRUE(io::file_exists(dir / kept)) << kept;
  EXPECT_FALSE(io::file_exists(dir / ".leftover.csv.millwear-tmp.1234.0"));
  EXPECT_FALSE(io::file_exists(dir / ".fig.millwear-tmp.1234.1.png"));
}

// ---- folder lock ----

TEST(IoFolderLock, ASecondLockIsRefusedNamingTheFolderAndTheHoldersPid) {
  TempDir dir{"millwear-io"};
  const std::string out = dir / "run";
  {
    io::FolderLock first(out);  // creates the folder
    EXPECT_TRUE(fs::is_directory(out));
    const std::string lock_text = io::read_file(first.path());
    EXPECT_EQ(io::find_value(io::parse_key_values(lock_text, first.path()), "pid"), std::to_string(::getpid()));
    EXPECT_NE(io::find_value(io::parse_key_values(lock_text, first.path()), "command"), "");
    try {
      io::FolderLock second(out);  // a second open file description: flock refuses it
      FAIL() << "expected InputError";
    } catch (const InputError& e) {
      const std::string m = e.what();
      EXPECT_NE(m.find(out), std::string::npos) << m;
      EXPECT_NE(m.find("process " + std::to_string(::getpid())), std::string::npos) << m;
    }
  }
  // Released: the lock file is gone, and so is the folder the lock made, left empty; it can
  // be locked again.
  EXPECT_FALSE(fs::exists(out));
  io::FolderLock again(out);
  EXPECT_TRUE(io::file_exists(again.path()));
}

// A released lock leaves the folder as it found it: a folder that was there stays (empty), a
// folder it made stays if something was written into it and goes if nothing was (the folders
// made on the way stay: other commands may be making theirs beside it).
TEST(IoFolderLock, ReleasedItLeavesTheFolderAsItFoundIt) {
  TempDir dir{"millwear-io"};
  const std::string there = dir / "there";
  fs::create_directories(there);
  { io::FolderLock lock(there); }
  EXPECT_TRUE(fs::is_directory(there));
  EXPECT_EQ(count_entries(there), 0);
  const std::string written = dir / "a/written";
  {
    io::FolderLock lock(written);
    io::write_file_atomic(written + "/result.csv", "x\n1\n");
  }
  EXPECT_TRUE(io::file_exists(written + "/result.csv"));
  EXPECT_EQ(count_entries(written), 1);
  const std::string empty = dir / "b/c/empty";
  { io::FolderLock lock(empty); }
  EXPECT_FALSE(fs::exists(empty));
  EXPECT_TRUE(fs::is_directory(dir / "b/c"));
}

// A command's lock marks its folder as its own: another command is refused it, naming the
// holder, and the mark stays with what was written. A command that wrote nothing leaves no
// mark, and any command may take the folder.
TEST(IoFolderLock, ACommandsFolderIsMarkedAndRefusedToAnotherCommand) {
  TempDir dir{"millwear-io"};
  const std::string out = dir / "hardness";
  {
    io::FolderLock lock(out, "hardness");
    // Marked, but nothing written yet: no results to claim (the lock keeps others out).
    EXPECT_EQ(io::folder_results_command(out), "");
    io::write_file_atomic(out + "/hardness_fit.csv", "x\n1\n");
  }
  EXPECT_EQ(io::folder_results_command(out), "hardness");
  { io::FolderLock again(out, "hardness"); }  // its own folder: taken again
  try {
    io::FolderLock other(out, "calibrate");
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_EQ(e.where, "-o");
    EXPECT_NE(std::string(e.what()).find("millwear hardness"), std::string::npos) << e.what();
  }
  EXPECT_EQ(io::folder_results_command(out), "hardness");

  const std::string empty = dir / "empty";
  fs::create_directories(empty);
  { io::FolderLock lock(empty, "validate"); }
  EXPECT_EQ(io::folder_results_command(empty), "");
  EXPECT_EQ(count_entries(empty), 0);
  { io::FolderLock lock(empty, "tradeoff"); }
}

// A command that only reads a run folder asks who holds it: the holder's pid while the lock
// is held, nobody once it is released.
TEST(IoFolderLock, TheHolderOfAFolderIsNamedWhileItHoldsIt) {
  TempDir dir{"millwear-io"};
  const std::string out = dir / "run";
  fs::create_directories(out);
  EXPECT_EQ(io::folder_holder(out), "");
  {
    io::FolderLock lock(out);
    EXPECT_NE(io::folder_holder(out).find("process " + std::to_string(::getpid())), std::string::npos)
        << io::folder_holder(out);
  }
  EXPECT_EQ(io::folder_holder(out), "");
}

TEST(IoFolderLock, AFolderThatCannotBeMadeIsAnInputErrorBeforeAnythingIsWritten) {
  TempDir dir{"millwear-io"};
  io::write_file_atomic(dir / "file", "a file, not a folder");
  try {
    io::check_output_folder(dir / "file/out");
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_EQ(e.where, "-o");
    EXPECT_NE(std::string(e.what()).find("file"), std::string::npos) << e.what();
  }
  EXPECT_EQ(count_entries(dir.path()), 1);
}

// A symbolic link that leads nowhere, as the folder or on the way to it, is bad input naming
// the link and why (it was "cannot create folder: File exists" or a file system error, after
// the command had started).
TEST(IoFolderLock, ASymbolicLinkThatLeadsNowhereIsAnInputErrorNamingIt) {
  TempDir dir{"millwear-io"};
  fs::create_symlink("missing-target", dir / "dangling");
  fs::create_symlink(dir / "loop-b", dir / "loop-a");
  fs::create_symlink(dir / "loop-a", dir / "loop-b");
  const std::pair<std::string, std::string> cases[] = {{dir / "dangling", "does not exist"},
                                                       {dir / "dangling/sub", "does not exist"},
                                                       {dir / "loop-a", "cannot be followed"}};
  for (const auto& [out, why] : cases) {
    try {
      io::check_output_folder(out);
      ADD_FAILURE() << "no InputError for " << out;
    } catch (const InputError& e) {
      EXPECT_EQ(e.where, "-o");
      EXPECT_NE(e.expected.find("is a symbolic link to '"), std::string::npos) << e.what();
      EXPECT_NE(e.expected.find(why), std::string::npos) << e.what();
    }
  }
  // A link to a folder is a folder.
  fs::create_directory(dir / "real");
  fs::create_directory_symlink(dir / "real", dir / "to-real");
  EXPECT_NO_THROW(io::check_output_folder(dir / "to-real"));
}

TEST(IoFolderLock, AFileGivenAsTheFolderIsAnInputErrorNamingIt) {
  TempDir dir{"millwear-io"};
  io::write_file_atomic(dir / "results", "a file, not a folder");
  try {
    io::FolderLock lock(dir / "results");
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_EQ(e.file, dir / "results");
    EXPECT_NE(std::string(e.what()).find("folder"), std::string::npos) << e.what();
  }
  EXPECT_EQ(io::read_file(dir / "results"), "a file, not a folder");
  EXPECT_THROW(io::check_output_folder(dir / "results"), InputError);
  EXPECT_NO_THROW(io::check_output_folder(dir / "not-yet"));
  EXPECT_FALSE(fs::exists(dir / "not-yet"));  // checking writes nothing
}

TEST(IoRunFolder, RemoveRunFilesDeletesOnlyListedFilesInsideTheFolder) {
  TempDir dir{"millwear-io"};
  const std::string out = dir / "out";
  io::create_run_folder(out);
  io::write_file_atomic(dir / "outside.csv", "x");
  for (const char* f : {"summary.csv", "profiles/a_stage0.csv", "notes.txt", "profiles/mine.csv"})
    io::write_file_atomic(io::join_path(out, f), "x");
  io::write_file_atomic(io::join_path(out, "stages/.a_stage0.record.millwear-tmp.99.0"), "x");
  const int n = io::remove_run_files(out, {"summary.csv", "profiles/a_stage0.csv", "../outside.csv",
                                           dir / "outside.csv", "missing.csv"});
  EXPECT_EQ(n, 3);  // two listed files and the temporary
  EXPECT_FALSE(io::file_exists(io::join_path(out, "summary.csv")));
  EXPECT_FALSE(io::file_exists(io::join_path(out, "profiles/a_stage0.csv")));
  EXPECT_TRUE(io::file_exists(io::join_path(out, "notes.txt")));
  EXPECT_TRUE(io::file_exists(io::join_path(out, "profiles/mine.csv")));
  EXPECT_TRUE(io::file_exists(dir / "outside.csv"));
  EXPECT_FALSE(fs::exists(io::stages_dir(out)));   // left empty: removed
  EXPECT_TRUE(fs::exists(io::profiles_dir(out)));  // still holds the user's file
}

// ---- CSV ----

TEST(IoCsv, ExactOptionRoundTripsEveryBit) {
  std::mt19937_64 rng(42);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  io::CsvOptions exact;
  exact.exact = true;
  io::CsvTable t({"design", "stage", "value"}, exact);
  std::vector<double> values;
  for (int i = 0; i < 200; ++i) {
    double v = u(rng) * std::pow(10.0, (i % 40) - 20);
    values.push_back(v);
    t.add_row({"2x30", i, v});
  }
  values.push_back(std::numeric_limits<double>::denorm_min());
  t.add_row({"2x30", 200, values.back()});
  io::CsvData d = io::parse_csv(t.str(), "mem.csv");
  ASSERT_EQ(d.row_count(), values.size());
  std::vector<double> back = d.numbers("value");
  for (std::size_t i = 0; i < values.size(); ++i)
    EXPECT_EQ(std::memcmp(&back[i], &values[i], sizeof(double)), 0) << i;
  EXPECT_EQ(d.text(3, d.column("stage")), "3");  // integers are written as integers
}

TEST(IoCsv, DefaultWritesTenSignificantDigits) {
  io::CsvTable t({"x"});
  t.add_row({1.0 / 3.0});
  t.add_row({12345.678901234});
  t.add_row({std::nan("")});
  EXPECT_EQ(t.str(), "x\n0.3333333333\n12345.6789\nnan\n");
}

// The fewest digits that read back as the value: what a person typed stays as typed, and two
// values one rounding apart never print alike.
TEST(IoCsv, ShortestTextReadsBackAsTheSameValue) {
  EXPECT_EQ(io::format_shortest(0.7), "0.7");
  EXPECT_EQ(io::format_shortest(0.7000000000000001), "0.7000000000000001");
  EXPECT_EQ(io::format_shortest(1e-300), "1e-300");
  EXPECT_EQ(io::format_shortest(-25.0), "-25");
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int i = 0; i < 500; ++i) {
    const double v = u(rng) * std::pow(10.0, (i % 60) - 30);
    const std::string text = io::format_shortest(v);
    EXPECT_EQ(std::strtod(text.c_str(), nullptr), v) << text;
  }
}

// A whole number is written as one, never in %g's exponent form of its fewest digits: a
// sweep over lifters.rows=10,20 or mill.speed_rpm=20,30 writes 10, 20, 30 in sweep.csv's
// value column, not 1e+01, 2e+01, 3e+01.
TEST(IoCsv, ShortestTextWritesWholeNumbersPlainly) {
  EXPECT_EQ(io::format_shortest(10.0), "10");
  EXPECT_EQ(io::format_shortest(20.0), "20");
  EXPECT_EQ(io::format_shortest(1500.0), "1500");
  EXPECT_EQ(io::format_shortest(-300.0), "-300");
  EXPECT_EQ(io::format_shortest(1000.0), "1000");
  EXPECT_EQ(io::format_shortest(0.0001), "0.0001");
  EXPECT_EQ(io::format_shortest(0.0), "0");
  EXPECT_EQ(io::format_shortest(1e20), "1e+20");
}

// Whole degrees as "%.0f" rounds them, without the "-0" of a toe at -0.3 deg.
TEST(Text, WholeDegreesRoundAsPrintfAndAreNeverMinusZero) {
  const auto shown = [](double v) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.0f", v);
    return std::string(buf);
  };
  for (const double deg : {-0.3, -0.5, 0.0, -0.0}) EXPECT_EQ(shown(millwear::whole_degrees(deg)), "0") << deg;
  for (const double deg : {0.5, 1.5, -1.5, 2.5, -42.6, 179.49, -0.51})
    EXPECT_EQ(shown(millwear::whole_degrees(deg)), shown(deg)) << deg;
}

TEST(IoCsv, FileRoundTripKeepsQuotedText) {
  TempDir dir{"millwear-io"};
  io::CsvTable t({"name", "note"});
  t.add_row({"a,b", "say \"hi\""});
  t.add_row({"plain", ""});
  t.write(dir / "t.csv");
  io::CsvData d = io::read_csv(dir / "t.csv");
  ASSERT_EQ(d.row_count(), 2u);
  EXPECT_EQ(d.text(0, 0), "a,b");
  EXPECT_EQ(d.text(0, 1), "say \"hi\"");
  EXPECT_EQ(d.text(1, 1), "");
  EXPECT_EQ(d.row_line[1], 3u);
}

TEST(IoCsv, RaggedRowErrorNamesFileAndLine) {
  TempDir dir{"millwear-io"};
  const std::string f = dir / "profile.csv";
  io::write_file_atomic(f, "x_mm,y_mm\n1,2\n\n3\n");
  try {
    io::read_csv(f);
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_EQ(e.file, f);
    EXPECT_EQ(e.where, "line 4");  // the blank line 3 is skipped but still counted
    EXPECT_NE(e.expected.find("2 fields"), std::string::npos) << e.expected;
  }
}

// Lines ended by a lone CR (a spreadsheet's "CSV (Macintosh)") are lines: counted in errors,
// and a '#' line among them is a comment (it read as one line, every error "line 1").
TEST(IoCsv, LinesEndedByALoneCarriageReturnAreLines) {
  const io::CsvData d = io::parse_csv(io::strip_comment_lines("# a comment\rx_mm,y_mm\r1,2\r3,abc\r"), "mac.csv");
  ASSERT_EQ(d.row_count(), 2u);
  EXPECT_EQ(d.header, (std::vector<std::string>{"x_mm", "y_mm"}));
  EXPECT_DOUBLE_EQ(d.number(0, "y_mm"), 2.0);
  try {
    d.numbers("y_mm");
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_EQ(e.where, "line 4");
  }
}

TEST(IoCsv, NonNumericFieldErrorNamesLineAndColumn) {
  io::CsvData d = io::parse_csv("x_mm,y_mm\r\n1,2\r\n3,abc\r\n", "p.csv");
  EXPECT_DOUBLE_EQ(d.number(0, "y_mm"), 2.0);
  try {
    d.numbers("y_mm");
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_EQ(e.file, "p.csv");
    EXPECT_EQ(e.where, "line 3");
    EXPECT_NE(e.expected.find("y_mm"), std::string::npos);
    EXPECT_NE(e.expected.find("abc"), std::string::npos);
  }
}

// A NUL byte inside a number is no end of it: "2\0" "0" and "20.25\0junk" are refused,
// naming the line and column, with the NUL shown as \x00 (a reader that stopped at the NUL
// read 2 and 20.25).
TEST(IoCsv, ANulByteInsideANumberIsRefusedAndShown) {
  for (const std::string& cell : {std::string("2\0" "0", 3), std::string("20.25\0junk", 10)}) {
    io::CsvData d = io::parse_csv("x_mm,y_mm\n1,2\n5," + cell + "\n", "p.csv");
    try {
      d.numbers("y_mm");
      FAIL() << "expected InputError";
    } catch (const InputError& e) {
      EXPECT_EQ(e.where, "line 3");
      EXPECT_NE(e.expected.find("y_mm"), std::string::npos);
      EXPECT_NE(e.expected.find("\\x00"), std::string::npos) << e.expected;
      EXPECT_EQ(e.expected.find('\0'), std::string::npos);
    }
  }
}

// A field of a million bytes is refused with its first bytes and its length, not echoed
// whole.
TEST(IoCsv, AHugeFieldIsShownCutShort) {
  const std::string cell(1000000, '7');
  io::CsvData d = io::parse_csv("x_mm,y_mm\n1,2\n5,x" + cell + "\n", "p.csv");
  try {
    d.numbers("y_mm");
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_EQ(e.where, "line 3");
    EXPECT_LT(e.expected.size(), 200u);
    EXPECT_NE(e.expected.find("(1000001 bytes)"), std::string::npos) << e.expected;
  }
}

// A column named twice is refused, naming it and both places; unnamed columns (a
// spreadsheet's trailing commas) are not names.
TEST(IoCsv, AColumnNamedTwiceIsRefused) {
  try {
    io::parse_csv("period,days,area_loss_mm2,hardness,days\n1,54,936.9,13.2,3\n", "d.csv");
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_EQ(e.file, "d.csv");
    EXPECT_EQ(e.where, "line 1");
    EXPECT_NE(e.expected.find("'days' as columns 2 and 5"), std::string::npos) << e.expected;
  }
  const io::CsvData d = io::parse_csv("x_mm,y_mm,,\n1,2,,\n", "p.csv");
  EXPECT_DOUBLE_EQ(d.number(0, "y_mm"), 2.0);
}

TEST(IoCsv, MissingColumnAndMissingFileAreInputErrors) {
  io::CsvData d = io::parse_csv("a,b\n1,2\n", "t.csv");
  EXPECT_THROW(d.column("c"), InputError);
  // A missing column names the header's own line, after blank (or stripped comment) lines.
  io::CsvData late = io::parse_csv("\n\na,b\n1,2\n", "t.csv");
  EXPECT_EQ(late.header_line, 3u);
  try {
    late.column("c");
    ADD_FAILURE() << "no error for a missing column";
  } catch (const InputError& e) {
    EXPECT_EQ(e.where, "line 3");
  }
  EXPECT_THROW(io::read_csv("/nonexistent/millwear/x.csv"), InputError);
  EXPECT_THROW(io::parse_csv("", "empty.csv"), InputError);
}

TEST(IoReadFile, AFileLargerThanAnyInputIsRefusedBeforeItIsRead) {
  // A sparse file: its size, not its bytes, is what the reader must look at first.
  const TempDir dir("millwear-io-huge");
  const fs::path huge = dir / "scan.csv";
  std::ofstream(huge) << "x_mm,y_mm\n";
  fs::resize_file(huge, io::kMaxInputFileBytes + 1);
  try {
    io::read_file(huge.string());
    ADD_FAILURE() << "not refused";
  } catch (const InputError& e) {
    EXPECT_EQ(e.file, huge.string());
    EXPECT_NE(e.expected.find("at most 256 MB"), std::string::npos) << e.expected;
  }
  std::ofstream(dir / "small.csv") << "x_mm,y_mm\n1,2\n";
  EXPECT_EQ(io::read_file((dir / "small.csv").string()), "x_mm,y_mm\n1,2\n");
}

TEST(IoCsv, ColumnNamesLoseTheBlanksAroundThem) {
  // As a spreadsheet or a hand may write them: "x_mm, y_mm", a tab, a quoted name.
  const io::CsvData d = io::parse_csv(" x_mm ,\ty_mm,\"hours \"\n1,2,3\n", "blanks.csv");
  EXPECT_EQ(d.header, (std::vector<std::string>{"x_mm", "y_mm", "hours"}));
  EXPECT_EQ(d.number(0, d.column("y_mm")), 2.0);
}

// ---- run folder ----

// Spreadsheets save CSV with a byte-order mark, CRLF line ends and, in much of Europe, ';'
// separators with decimal commas. Each is read as the table it is.
TEST(IoCsv, AByteOrderMarkIsNotPartOfTheFirstColumnName) {
  const io::CsvData d = io::parse_csv("\xEF\xBB\xBFhours,area_mm2\n0,431.5\n", "excel.csv");
  EXPECT_EQ(d.header.front(), "hours");
  EXPECT_EQ(d.number(0, d.column("hours")), 0.0);
  EXPECT_EQ(d.number(0, "area_mm2"), 431.5);
}

TEST(IoCsv, CrlfLineEndsReadAsLf) {
  const io::CsvData d = io::parse_csv("hours,\"x_mm\"\r\n0,1.5\r\n\r\n100,-2\r\n", "crlf.csv");
  ASSERT_EQ(d.header, (std::vector<std::string>{"hours", "x_mm"}));
  ASSERT_EQ(d.row_count(), 2u);
  EXPECT_EQ(d.number(1, "x_mm"), -2.0);
  EXPECT_EQ(d.row_line[1], 4u);  // the blank line still counts
}

TEST(IoCsv, SemicolonFilesReadWithDecimalCommas) {
  const io::CsvData d =
      io::parse_csv("\xEF\xBB\xBFhours;area_mm2;note\r\n0;431,5;\"new; clean\"\r\n100;400.25;a,b\r\n", "eu.csv");
  EXPECT_EQ(d.separator, ';');
  ASSERT_EQ(d.header, (std::vector<std::string>{"hours", "area_mm2", "note"}));
  EXPECT_EQ(d.number(0, "area_mm2"), 431.5);
  EXPECT_EQ(d.number(1, "area_mm2"), 400.25);  // a point still reads
  EXPECT_EQ(d.text(0, 2), "new; clean");
  EXPECT_EQ(d.text(1, 2), "a,b");  // a comma is text in a ';' file
  // In a ',' file a comma is never a decimal separator.
  EXPECT_EQ(io::parse_csv("a,b\n1,2\n", "c.csv").separator, ',');
}

// European Excel writes 1000 h as "1.000" where it writes 385.5 as "385,5": in a ';' file that
// writes decimal commas, digits grouped in threes after points are a thousands separator,
// which strtod read as 1 h with exit 0. Refused naming the line and the comma that shows it;
// a file without decimal commas keeps the point as its decimal point.
TEST(IoCsv, SemicolonFilesWithDecimalCommasRefuseAThousandsPoint) {
  const io::CsvData d = io::parse_csv("hours;area_mm2\n0;419\n50;385,5\n1.000;355\n2.5;-12.500.000\n", "eu.csv");
  EXPECT_EQ(d.number(1, "area_mm2"), 385.5);
  EXPECT_EQ(d.number(2, "area_mm2"), 355.0);
  EXPECT_EQ(d.number(3, "hours"), 2.5);  // not in groups of three: a decimal point still
  for (const auto& [row, col, line, found] : {std::tuple<std::size_t, const char*, const char*, const char*>{
                                                  2, "hours", "line 4", "'1.000'"},
                                              {3, "area_mm2", "line 5", "'-12.500.000'"}}) {
    try {
      d.number(row, col);
      ADD_FAILURE() << "read " << found << " as " << d.number(row, col);
    } catch (const InputError& e) {
      EXPECT_EQ(e.file, "eu.csv");
      EXPECT_EQ(e.where, line);
      EXPECT_NE(e.expected.find(found), std::string::npos) << e.what();
      EXPECT_NE(e.expected.find("'385,5' on line 3"), std::string::npos) << e.what();
    }
  }
  const io::CsvData points = io::parse_csv("hours;area_mm2\n0;419\n1.000;355\n", "points.csv");
  EXPECT_EQ(points.number(1, "hours"), 1.0);
}

TEST(IoCsv, SemicolonFileErrorsNameFileLineAndWhatWasExpected) {
  try {
    io::parse_csv("hours;area_mm2\n0;431,5\n100\n", "eu.csv");
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_EQ(e.file, "eu.csv");
    EXPECT_EQ(e.where, "line 3");
    EXPECT_NE(e.expected.find("2 fields"), std::string::npos) << e.what();
  }
  const io::CsvData d = io::parse_csv("hours;area_mm2\n0;1.431,5\n", "eu.csv");
  try {
    d.number(0, "area_mm2");  // a thousands separator is refused, not guessed at
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_EQ(e.file, "eu.csv");
    EXPECT_EQ(e.where, "line 2");
    EXPECT_NE(e.expected.find("area_mm2"), std::string::npos) << e.what();
    EXPECT_NE(e.expected.find("1.431,5"), std::string::npos) << e.what();
  }
  try {
    io::parse_csv(std::string("\xFF\xFEh\0", 5), "utf16.csv");
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_EQ(e.file, "utf16.csv");
    EXPECT_EQ(e.where, "line 1");
    EXPECT_NE(e.expected.find("UTF-8"), std::string::npos) << e.what();
  }
}

TEST(IoRunFolder, PathConventions) {
  EXPECT_EQ(io::stage_done_marker("OUT", "2x30", 3), "OUT/stages/2x30_stage3.done");
  EXPECT_EQ(io::profile_path("OUT/", "1x30", 0), "OUT/profiles/1x30_stage0.csv");
  EXPECT_EQ(io::plots_data_dir("OUT"), "OUT/plots/data");
  EXPECT_TRUE(io::is_valid_design_name("2x30"));
  EXPECT_FALSE(io::is_valid_design_name("../x"));
  EXPECT_FALSE(io::is_valid_design_name("a b"));
}

// A folder no command marked holds the user's files: a command other than run takes it only
// empty, and one marked by the command itself is its own to rewrite.
TEST(IoRunFolder, AnUnmarkedFolderWithFilesIsNotTakenByACommand) {
  TempDir dir{"millwear-io-taken"};
  EXPECT_NO_THROW(io::check_folder_not_taken(dir.path(), "charge"));  // empty
  // Hidden files (a file manager's, a killed command's temporaries) are no one's results.
  io::write_file_atomic(dir / ".DS_Store", "x");
  io::write_file_atomic(dir / ".summary.csv.millwear-tmp.123.0", "x");
  EXPECT_NO_THROW(io::check_folder_not_taken(dir.path(), "charge"));
  io::write_file_atomic(dir / "notes.txt", "mine");
  io::write_file_atomic(dir / "spectrum.csv", "mine too");
  try {
    io::check_folder_not_taken(dir.path(), "charge");
    ADD_FAILURE() << "taken";
  } catch (const InputError& e) {
    EXPECT_EQ(e.where, "-o");
    EXPECT_NE(std::string(e.what()).find("this folder holds notes.txt and 1 more, of no millwear command's results"),
              std::string::npos)
        << e.what();
  }
  io::mark_folder(dir.path(), "charge");
  EXPECT_NO_THROW(io::check_folder_not_taken(dir.path(), "charge"));
  EXPECT_THROW(io::check_folder_not_taken(dir.path(), "sweep"), InputError);
  // A mark with nothing visible beside it (a command killed before it wrote) claims nothing.
  TempDir killed{"millwear-io-killed"};
  io::mark_folder(killed.path(), "charge");
  io::write_file_atomic(killed / ".millwear.lock", "pid=1\n");
  EXPECT_EQ(io::folder_results_command(killed.path()), "");
  EXPECT_NO_THROW(io::check_folder_not_taken(killed.path(), "sweep"));
  // A screen folder written before folders were marked is known by its screen.key.
  TempDir old_screen{"millwear-io-old-screen"};
  io::write_file_atomic(old_screen / "screen.key", "x");
  io::write_file_atomic(old_screen / "designs.csv", "x");
  EXPECT_EQ(io::folder_results_command(old_screen.path()), "screen");
  EXPECT_NO_THROW(io::check_folder_not_taken(old_screen.path(), "screen"));
  EXPECT_THROW(io::check_folder_not_taken(old_screen.path(), "charge"), InputError);
}

TEST(IoRunFolder, FinishedStagesAreListedAndTheLastContiguousFound) {
  TempDir dir{"millwear-io"};
  io::create_run_folder(dir.path());
  io::write_stage_done(dir.path(), "2x30", 0, {{"hours", "0"}});
  io::write_stage_done(dir.path(), "2x30", 1, {{"hours", "750"}});
  io::write_stage_done(dir.path(), "2x30", 3, {{"hours", "2250"}});
  io::write_stage_done(dir.path(), "2x30_b", 2);  // another design sharing the prefix
  // A marker whose content disagrees with its name is not trusted.
  io::write_file_atomic(io::stage_done_marker(dir.path(), "2x30", 2), "design=1x30\nstage=2\n");
  EXPECT_EQ(io::list_finished_stages(dir.path(), "2x30"), (std::vector<int>{0, 1, 3}));
  EXPECT_EQ(io::last_finished_stage(dir.path(), "2x30"), 1);
  EXPECT_EQ(io::last_finished_stage(dir.path(), "1x30"), -1);
  auto kv = io::read_key_values(io::stage_done_marker(dir.path(), "2x30", 1));
  EXPECT_EQ(io::find_value(kv, "design"), "2x30");
  EXPECT_EQ(io::find_value(kv, "hours"), "750");
}

TEST(IoRunFolder, KeyValueSyntaxErrorNamesLine) {
  auto kv = io::parse_key_values("# c\n a = b = c \n\nempty=\n", "m.done");
  ASSERT_EQ(kv.size(), 2u);
  EXPECT_EQ(kv[0].first, "a");
  EXPECT_EQ(kv[0].second, "b = c");
  EXPECT_EQ(kv[1].second, "");
  try {
    io::parse_key_values("a=1\nnot a pair\n", "m.done");
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_EQ(e.file, "m.done");
    EXPECT_EQ(e.where, "line 2");
  }
}


// ---- Resume keys ----

// FNV-1a 64 has published check values; the same bytes give the same key on every platform
// (std::hash gives none of these guarantees).
TEST(IoHash, StableHashMatchesTheFnv1aCheckValues) {
  EXPECT_EQ(millwear::io::stable_hash_hex(""), "cbf29ce484222325");
  EXPECT_EQ(millwear::io::stable_hash_hex("a"), "af63dc4c8601ec8c");
  EXPECT_EQ(millwear::io::stable_hash_hex("foobar"), "85944171f73967e8");
  EXPECT_NE(millwear::io::stable_hash_hex("scene\n--\nprofile"), millwear::io::stable_hash_hex("scene\n--\nprofilf"));
}

// A message naming a staged file (a figure's error) names it where commit puts it, in OUT;
// until commit OUT holds the earlier run's files as they were; commit moves the new ones in,
// deletes the earlier run's listed files that no new one replaced (not a user's, not one of
// `keep`) and the staging folder.
TEST(StagedOutputs, AMessageNamesTheStagedFileWhereCommitPutsIt) {
  const TempDir dir("millwear-staged-outputs");
  const std::string out = (dir / "out").string();
  dir.write("out/manifest.json", "{\"files\": [\"manifest.json\", \"a.csv\", \"old/b.csv\", \"scene.toml\"]}\n");
  dir.write("out/a.csv", "earlier a\n");
  dir.write("out/old/b.csv", "earlier b\n");
  dir.write("out/scene.toml", "the input\n");
  dir.write("out/notes.txt", "the user's\n");
  {
    io::StagedOutputs staged(out);
    const std::string a = io::join_path(staged.dir(), "a.csv");
    io::write_file_atomic(a, "new a\n");
    io::write_file_atomic(io::join_path(staged.dir(), "manifest.json"), "{\"files\": [\"manifest.json\", \"a.csv\"]}\n");
    EXPECT_EQ(staged.in_out(a), io::join_path(out, "a.csv"));
    EXPECT_EQ(staged.in_out_text("cannot read " + a + " nor " + a), "cannot read " + io::join_path(out, "a.csv") +
                                                                        " nor " + io::join_path(out, "a.csv"));
    EXPECT_EQ(io::read_file((dir / "out/a.csv").string()), "earlier a\n");  // not yet
    staged.commit({(dir / "out/scene.toml").string()});
  }
  EXPECT_EQ(io::read_file((dir / "out/a.csv").string()), "new a\n");
  EXPECT_FALSE(fs::exists(dir / "out/old")) << "the earlier run's file, and the folder it leaves empty";
  EXPECT_TRUE(fs::exists(dir / "out/scene.toml"));
  EXPECT_TRUE(fs::exists(dir / "out/notes.txt"));
  EXPECT_FALSE(fs::exists(dir / "out" / io::kStagingName));
}
