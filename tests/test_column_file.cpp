#include <gtest/gtest.h>

#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>

#include "mlce/reader/column_file.hpp"

using namespace mlce::reader;

TEST(ColumnFile, ParsesWhitespaceCommasAndComments) {
  const Table t = parse_column_text("# header\n0 1.5\n\n0.1,\t-2e-3  # trailing\n+0.2 3\n", "mem");
  ASSERT_EQ(t.columns.size(), 2u);
  ASSERT_EQ(t.rows(), 3u);
  EXPECT_DOUBLE_EQ(t.columns[1][1], -2e-3);
  EXPECT_DOUBLE_EQ(t.columns[0][2], 0.2);
  EXPECT_EQ(t.line_of(1), 4u);
  EXPECT_EQ(t.where(2), "mem:5");
}

TEST(ColumnFile, KeepsRequestedColumns) {
  ColumnFileOptions o;
  o.keep = {3, 1};
  const Table t = parse_column_text("1 2 3\n4 5 6\n", "mem", o);
  ASSERT_EQ(t.columns.size(), 2u);
  EXPECT_DOUBLE_EQ(t.columns[0][1], 6.0);
  EXPECT_DOUBLE_EQ(t.columns[1][1], 4.0);
}

namespace {
std::string error_of(const std::string& text) {
  try {
    parse_column_text(text, "f.txt");
  } catch (const ReadError& e) {
    return e.what();
  }
  return "";
}
}  // namespace

TEST(ColumnFile, ErrorsNameFileLineAndExpectation) {
  EXPECT_EQ(error_of("1 2\n3 abc\n"), "f.txt:2: column 2: 'abc' is not a number");
  EXPECT_EQ(error_of("1 2\n3 nan\n"), "f.txt:2: column 2: 'nan': expected a finite number");
  EXPECT_EQ(error_of("1 2\ninf 2\n"), "f.txt:2: column 1: 'inf': expected a finite number");
  EXPECT_EQ(error_of("1 2\n3\n"), "f.txt:2: 1 column(s), expected 2 as on the first data line");
  EXPECT_EQ(error_of("# only comments\n\n"), "f.txt: no data (the file is empty or holds only comments)");
  EXPECT_EQ(error_of(""), "f.txt: no data (the file is empty or holds only comments)");
  EXPECT_EQ(error_of("1 1e999\n"), "f.txt:1: column 2: '1e999' is out of the range of a double");
}

TEST(ColumnFile, FortranDoublePrecisionExponentsAreNumbers) {
  const Table t = parse_column_text("0.0 1.0D+00\n0.1 -2.5d-01\n0.2 3D2\n0.3 +4.0D0\n", "mem");
  ASSERT_EQ(t.rows(), 4u);
  EXPECT_EQ(t.columns[1], (std::vector<double>{1.0, -0.25, 300.0, 4.0}));
  EXPECT_EQ(error_of("1 1.0Dx\n"), "f.txt:1: column 2: '1.0Dx' is not a number");
  EXPECT_EQ(error_of("1 1D+999\n"), "f.txt:1: column 2: '1D+999' is out of the range of a double");
  EXPECT_EQ(error_of("0 1\n0;1 2\n"), "f.txt:2: column 1: '0;1' is not a number (fields are separated by spaces, tabs or "
                                       "commas; by semicolons when the file's first line is)");
}

TEST(ColumnFile, MissingFileIsAnError) {
  EXPECT_THROW(read_column_file("/nonexistent/file.txt"), ReadError);
}

TEST(ColumnFile, AHeaderLineNamesTheColumns) {
  // As `mlce extract` and spreadsheets write CSV: the first non-comment line, all words.
  ColumnFileOptions o;
  o.keep = {2};
  const Table t = parse_column_text("# run 7\ntime,rel:13:4:z\n0,0.5\n0.005,0.25\n", "mem", o);
  ASSERT_EQ(t.rows(), 2u);
  EXPECT_EQ(t.names.at(0), "rel:13:4:z");
  EXPECT_DOUBLE_EQ(t.columns[0][1], 0.25);
  EXPECT_EQ(t.line_of(0), 3u);
  // Only the first line can be a header, only when no field reads as a number, and it must name
  // every column.
  EXPECT_EQ(error_of("a b\n1 2\nc d\n"), "f.txt:3: column 1: 'c' is not a number");
  EXPECT_EQ(error_of("t 1\n1 2\n"), "f.txt:1: column 1: 't' is not a number");
  EXPECT_EQ(error_of("nan x\n1 2\n"), "f.txt:1: column 1: 'nan': expected a finite number");
  EXPECT_EQ(error_of("a b c\n1 2\n"), "f.txt:2: 2 column(s), but the header on line 1 names 3");
  EXPECT_EQ(error_of("a b\n"), "f.txt: no data (the file is empty or holds only comments)");
}

TEST(ColumnFile, TheLastCommentBeforeTheDataNamesTheColumnsWhenItNamesEachOne) {
  // `# time x_h`, as make_series, `mlce simulate --format columns` and numpy.savetxt(header=...)
  // write it (numpy's genfromtxt(names=True) reads it so): one word per column.
  const Table t = parse_column_text("# lorenz, dt = 0.01\n# time value\n\n0 1.5\n0.01 2.5\n", "mem");
  ASSERT_EQ(t.names, (std::vector<std::string>{"time", "value"}));
  EXPECT_TRUE(t.has_header);
  EXPECT_EQ(t.line_of(0), 4u);
  EXPECT_EQ(parse_column_text("#t,x\n0,1\n", "mem").names, (std::vector<std::string>{"t", "x"}));
  // Another count, a number among the words, or a comment that is not the last before the data:
  // a comment, and the columns unnamed.
  for (const char* text : {"# time x y\n0 1\n", "# time 2\n0 1\n", "# time value\n# run 7\n0 1\n", "# 0.5 x\n0 1\n"}) {
    const Table u = parse_column_text(text, "mem");
    EXPECT_FALSE(u.has_header) << text;
    EXPECT_EQ(u.names, (std::vector<std::string>{"column 1", "column 2"})) << text;
  }
  // A header line outside a comment wins, and a comment after the first row names nothing.
  EXPECT_EQ(parse_column_text("# a b\nt v\n0 1\n", "mem").names, (std::vector<std::string>{"t", "v"}));
  EXPECT_FALSE(parse_column_text("0 1\n# a b\n2 3\n", "mem").has_header);
}

TEST(ColumnFile, AByteOrderMarkIsNotPartOfTheFirstLine) {
  // Spreadsheets' "CSV UTF-8" starts with EF BB BF: the comment or header behind it still reads.
  const Table c = parse_column_text("\xEF\xBB\xBF# run 7\n0 1\n1 2\n", "mem");
  EXPECT_EQ(c.rows(), 2u);
  const Table h = parse_column_text("\xEF\xBB\xBFtime,x\r\n0,1\r\n1,2\r\n", "mem");
  ASSERT_EQ(h.rows(), 2u);
  EXPECT_EQ(h.names.at(0), "time");
  EXPECT_DOUBLE_EQ(h.columns[1][1], 2.0);
}

TEST(ColumnFile, AnEmptyFieldIsRefusedNotSkipped) {
  // Skipping a missing value would move every later field one column to the left, so that
  // "--column 3" read what is column 4 in the spreadsheet the file came from.
  EXPECT_EQ(error_of("0,1,2\n0.1,,3\n"), "f.txt:2: column 2: empty field: expected a number");
  EXPECT_EQ(error_of("0,1,2\n,4,3\n"), "f.txt:2: column 1: empty field: expected a number");
  EXPECT_EQ(error_of("0, ,2\n"), "f.txt:1: column 2: empty field: expected a number");
  EXPECT_EQ(error_of("0,,\n"), "f.txt:1: column 2: empty field: expected a number");
  // One comma between blanks is one separator; a comma ending the line opens no field.
  const Table t = parse_column_text("0 , 1 ,\t2,\n0.1,\t4 ,5 ,  \n", "mem");
  ASSERT_EQ(t.columns.size(), 3u);
  EXPECT_EQ(t.columns[2], (std::vector<double>{2.0, 5.0}));
  // A header cell left empty is a column without a name: the columns after it keep their places.
  ColumnFileOptions o;
  o.keep = {3};
  const Table u = parse_column_text("time,,x\n0,7,0.5\n0.1,8,0.25\n", "mem", o);
  EXPECT_TRUE(u.has_header);
  EXPECT_EQ(u.names.at(0), "x");
  EXPECT_EQ(u.columns[0], (std::vector<double>{0.5, 0.25}));
  EXPECT_EQ(error_of(",,\n1,2\n"), "f.txt:1: column 1: empty field: expected a number");  // commas only: no header
}

TEST(ColumnFile, QuotedFieldsReadAsTheirText) {
  // R's write.csv: a quoted header whose first cell (the row names') is empty, and quoted row names.
  const Table r = parse_column_text("\"\",\"time\",\"x\"\n\"1\",0,0.5\n\"2\",0.01,-0.25\n", "mem");
  ASSERT_EQ(r.columns.size(), 3u);
  EXPECT_EQ(r.names, (std::vector<std::string>{"", "time", "x"}));  // the row names' column has no name
  EXPECT_EQ(r.columns[0], (std::vector<double>{1.0, 2.0}));
  EXPECT_EQ(r.columns[2], (std::vector<double>{0.5, -0.25}));
  // A separator or a '#' inside the quotes is text; "" inside is a quote of the name.
  const Table n = parse_column_text("\"t, s\"\t\"x#1\"\t\"say \"\"hi\"\"\"\n0 1 2\n", "mem");
  EXPECT_EQ(n.names, (std::vector<std::string>{"t, s", "x#1", "say \"\"hi\"\""}));
  EXPECT_EQ(n.columns[2], (std::vector<double>{2.0}));
  // Quoted text among the data, a quote that never closes, and text after a closing quote: refused.
  EXPECT_EQ(error_of("0,1\n\"a\",2\n"), "f.txt:2: column 1: 'a' is not a number");
  EXPECT_EQ(error_of("0,1\n\"1,2\n"), "f.txt:2: column 1: '\"1' is not a number");
  EXPECT_EQ(error_of("0,1\n\"1\"2,2\n"), "f.txt:2: column 1: '\"1\"2' is not a number");
  EXPECT_EQ(error_of("0,1\n\"\",2\n"), "f.txt:2: column 1: empty field: expected a number");
}

TEST(ColumnFile, TextWithBlanksIsOneFieldOfACommaSeparatedLine) {
  // pandas writes datetimes as "2026-11-27 01:00:00", unquoted: between commas, one field of text.
  ColumnFileOptions o;
  o.keep = {2, 3};
  const Table t = parse_column_text("when,t,x\n2026-11-27 01:00:00,0,0.5\n2026-11-27 01:00:01, 1 ,0.25\n", "mem", o);
  EXPECT_EQ(t.names, (std::vector<std::string>{"t", "x"}));
  EXPECT_EQ(t.columns[0], (std::vector<double>{0.0, 1.0}));
  EXPECT_EQ(t.columns[1], (std::vector<double>{0.5, 0.25}));
  // Tab-separated, as MATLAB's writetable and spreadsheets write dates: the date is one field, a run
  // of tabs one separator; numbers aligned by spaces and tabs alike stay numbers.
  const Table tab = parse_column_text("when\tt\tx\n27-Nov-2026 01:00:00\t0\t\t0.5\n27-Nov-2026 01:00:01\t 1\t0.25\n", "mem", o);
  EXPECT_EQ(tab.names, (std::vector<std::string>{"t", "x"}));
  EXPECT_EQ(tab.columns[1], (std::vector<double>{0.5, 0.25}));
  const Table aligned = parse_column_text("0  1.5\t2\n1 \t2.5   3\n", "mem");
  ASSERT_EQ(aligned.columns.size(), 3u);
  EXPECT_EQ(aligned.columns[1], (std::vector<double>{1.5, 2.5}));
  // A header whose names hold blanks names as many columns as it has commas.
  EXPECT_EQ(parse_column_text("time s, x m\n0,1\n", "mem").names, (std::vector<std::string>{"time s", "x m"}));
  // Numbers between semicolons and decimal commas in a comma-separated file (its first line says so):
  // refused however the columns are read (its first column would read as the integer parts); a note
  // with a semicolon is text.
  ColumnFileOptions text;
  text.text_columns = true;
  for (const auto& options : {ColumnFileOptions{}, text})
    try {
      parse_column_text("t,x\n0,01;2,5\n0,02;2,6\n", "f.txt", options);
      ADD_FAILURE() << "read";
    } catch (const ReadError& e) {
      EXPECT_STREQ(e.what(), "f.txt:2: column 2: '01;2' is not a number (fields are separated by spaces, tabs or commas; "
                             "by semicolons when the file's first line is)");
    }
  EXPECT_EQ(parse_column_text("t,x,note\n0,1,a;b\n", "mem", text).text[2].message,
            "mem:2: column 3: 'a;b' is not a number (fields are separated by spaces, tabs or commas; by semicolons "
            "when the file's first line is)");
  // Without asking for the columns it reads, the text stops the read where it stands.
  EXPECT_EQ(error_of("t,x\n2026-11-27 01:00:00,0.5\n"), "f.txt:2: column 1: '2026-11-27 01:00:00' is not a number");
}

TEST(ColumnFile, SemicolonSeparatedFilesWithDecimalCommasReadAsSpreadsheetsWriteThem) {
  // Excel and LibreOffice in a locale whose decimal mark is a comma (it, de, fr, ...) save CSV so.
  const Table t = parse_column_text("\xEF\xBB\xBFtime;x\r\n0,01;-2,5\r\n0,02;1,25E-03\r\n0,03; 3 \r\n", "mem");
  EXPECT_EQ(t.names, (std::vector<std::string>{"time", "x"}));
  EXPECT_EQ(t.columns[0], (std::vector<double>{0.01, 0.02, 0.03}));
  EXPECT_EQ(t.columns[1], (std::vector<double>{-2.5, 1.25e-3, 3.0}));
  // Without a header, with decimal points, quoted names, a comment naming the columns, a semicolon
  // ending every line, a Fortran exponent: the same rules as for commas.
  EXPECT_EQ(parse_column_text("0.5;1\n1.5;2\n", "mem").columns[0], (std::vector<double>{0.5, 1.5}));
  EXPECT_EQ(parse_column_text("\"t s\";\"x;1\"\n0;1\n", "mem").names, (std::vector<std::string>{"t s", "x;1"}));
  EXPECT_EQ(parse_column_text("# t;x\n0;1,5\n", "mem").names, (std::vector<std::string>{"t", "x"}));
  EXPECT_EQ(parse_column_text("0;1,5;\n1;2,5;\n", "mem").columns.size(), 2u);
  EXPECT_EQ(parse_column_text("0;1,0D+01\n", "mem").columns[1], (std::vector<double>{10.0}));
  // A thousands separator, two commas, an empty field, a row of another separator: one error each,
  // never a number read another way.
  EXPECT_EQ(error_of("t;x\n0;1.234,5\n"), "f.txt:2: column 2: '1.234,5' is not a number (a semicolon-separated file's "
                                          "numbers have one decimal comma or point, no thousands separators)");
  EXPECT_EQ(error_of("t;x\n0;1,2,3\n"), "f.txt:2: column 2: '1,2,3' is not a number (a semicolon-separated file's "
                                        "numbers have one decimal comma or point, no thousands separators)");
  EXPECT_EQ(error_of("t;x\n0;;\n"), "f.txt:2: column 2: empty field: expected a number");
  EXPECT_EQ(error_of("t;x\n0,1;2\n0,2 3\n"), "f.txt:3: column 1: '0,2 3' is not a number");
  EXPECT_EQ(error_of("t;x\n0;1,5e999\n"), "f.txt:2: column 2: '1,5e999' is out of the range of a double");
  // A first line that splits at its semicolons into neither names nor numbers leaves the file as it was.
  EXPECT_EQ(error_of("0,1,a;b\n"), "f.txt:1: column 3: 'a;b' is not a number (fields are separated by spaces, tabs or "
                                   "commas; by semicolons when the file's first line is)");
}

TEST(ColumnFile, TextColumnsAreMarkedAndRefusedOnlyWhereAsked) {
  // A spreadsheet's label and date columns beside the numbers: read on, each column says where its
  // first field of text is, and a caller refuses text only in the columns it analyses.
  ColumnFileOptions o;
  o.text_columns = true;
  const Table t = parse_column_text("# run 7\nlabel,t,x,note\nA,0,0.5,ok\nB,0.1,0.25,\nC,0.2,*****,\n", "f.txt", o);
  ASSERT_EQ(t.columns.size(), 4u);
  ASSERT_EQ(t.text.size(), 4u);
  EXPECT_EQ(t.text[0].line, 3u);
  EXPECT_EQ(t.text[0].message, "f.txt:3: column 1: 'A' is not a number");
  EXPECT_EQ(t.text[1].line, 0u);  // a column of numbers
  EXPECT_EQ(t.text[2].message, "f.txt:5: column 3: '*****' is not a number");
  EXPECT_EQ(t.text[3].message, "f.txt:3: column 4: 'ok' is not a number");
  // "0.25," ends its row one field short: the last value is missing (pandas), not one column fewer.
  EXPECT_EQ(t.columns[3].size(), 3u);
  EXPECT_TRUE(std::isnan(t.columns[3][1]));
  EXPECT_TRUE(std::isnan(t.columns[2][2]));
  EXPECT_NO_THROW(t.require_numbers({1}));
  EXPECT_NO_THROW(t.require_numbers({1, 2}, 4));  // x up to line 4: numbers
  auto refusal = [&](const std::vector<std::size_t>& which) {
    try {
      t.require_numbers(which);
    } catch (const ReadError& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  // The file's order decides which is reported: line 3 before line 5, column 1 before column 4.
  EXPECT_EQ(refusal({2, 3}), "f.txt:3: column 4: 'ok' is not a number");
  EXPECT_EQ(refusal({3, 0}), "f.txt:3: column 1: 'A' is not a number");
  EXPECT_EQ(refusal({2}), "f.txt:5: column 3: '*****' is not a number");
  // Columns kept by number read only those fields: text elsewhere is no error.
  ColumnFileOptions k;
  k.keep = {3, 2};
  const Table u = parse_column_text("A,0,0.5,ok\nB,0.1,0.25,x\n", "mem", k);
  EXPECT_EQ(u.columns[0], (std::vector<double>{0.5, 0.25}));
  EXPECT_TRUE(u.text.empty());
}

TEST(ColumnFile, DecimalCommasAreRefusedNotReadAsMoreColumns) {
  // A spreadsheet with decimal commas and tabs between fields: every row would read as four
  // consistent columns of wrong numbers. A line that separates some fields by commas and others by
  // blanks only is refused.
  EXPECT_EQ(error_of("0,01\t2,5\n0,02\t2,6\n"),
            "f.txt:1: '0,01\\t2,5': fields separated by commas and by blanks alike (decimal commas?): write "
            "decimal points, and one kind of separator");
  EXPECT_EQ(error_of("1 2\n3 4,5\n"), "f.txt:2: '3 4,5': fields separated by commas and by blanks alike (decimal "
                                        "commas?): write decimal points, and one kind of separator");
  // Commas with blanks around them, or blanks alone, are one kind each.
  EXPECT_EQ(parse_column_text("0 , 1,\t2\n3 4 5\n", "mem").columns.size(), 3u);
}

TEST(ColumnFile, AFileIsStreamedAcrossItsReadBufferAndItsLastLineNeedsNoNewline) {
  // The reader holds the table, never the file's text: rows cross the 1 MiB read buffer's edges,
  // and a file saved without a final newline (many editors) keeps its last row.
  namespace fs = std::filesystem;
  const fs::path path = fs::temp_directory_path() / ("mlce_stream_" + std::to_string(::getpid()) + ".csv");
  const std::size_t rows = 300000;  // about 4.6 MB: several buffer refills
  {
    std::ofstream out(path, std::ios::binary);
    out.precision(17);
    out << "\xEF\xBB\xBFtime,x\r\n";
    for (std::size_t i = 0; i < rows; ++i) out << i << "," << 0.5 * static_cast<double>(i) << (i + 1 < rows ? "\r\n" : "");
  }
  const Table t = read_column_file(path.string());
  ASSERT_EQ(t.rows(), rows);
  EXPECT_EQ(t.names, (std::vector<std::string>{"time", "x"}));
  for (std::size_t i = 0; i < rows; ++i) {
    ASSERT_EQ(t.columns[0][i], static_cast<double>(i)) << "row " << i;
    ASSERT_EQ(t.columns[1][i], 0.5 * static_cast<double>(i)) << "row " << i;
  }
  EXPECT_EQ(t.where(rows - 1), path.string() + ":" + std::to_string(rows + 1));
  fs::remove(path);
  // A directory is not a file of columns: one error naming it, no crash.
  const std::string dir = fs::temp_directory_path().string();
  try {
    read_column_file(dir);
    ADD_FAILURE() << "a directory was read";
  } catch (const ReadError& e) {
    EXPECT_NE(std::string(e.what()).find(dir), std::string::npos) << e.what();
  }
}

TEST(ColumnFile, ALastLineCutShortWhileTheFileIsWrittenIsLeftOutWithAWarning) {
  // A run still writing its file (or a copy taken meanwhile) ends in a part of a line: fewer fields
  // than the rows before it, or a field cut inside its exponent, and no line end.
  for (const char* tail : {"3", "3 ", "3 4e", "3,"}) {
    const std::string text = std::string("0 1\n1 2\n# c\n2 3\n") + tail;
    const Table t = parse_column_text(text, "mem");
    EXPECT_EQ(t.rows(), 3u) << tail;
    ASSERT_EQ(t.warnings.size(), 1u) << tail;
    EXPECT_NE(t.warnings[0].find("mem:5: the last line has no line end and "), std::string::npos) << t.warnings[0];
    EXPECT_NE(t.warnings[0].find("It is left out"), std::string::npos) << t.warnings[0];
  }
  EXPECT_NE(parse_column_text("0 1\n1 2\n3 4e", "mem").warnings.at(0).find("a field that is no number"), std::string::npos);
  EXPECT_NE(parse_column_text("0 1\n1 2\n3", "mem").warnings.at(0).find("1 of the 2 fields"), std::string::npos);
  // A complete last line without a line end is a row; a short line with one is an error, as any.
  EXPECT_EQ(parse_column_text("0 1\n1 2\n3 4", "mem").rows(), 3u);
  EXPECT_TRUE(parse_column_text("0 1\n1 2\n3 4", "mem").warnings.empty());
  EXPECT_THROW(parse_column_text("0 1\n1 2\n3\n", "mem"), ReadError);
  EXPECT_THROW(parse_column_text("0 1\n1 2e\n3 4", "mem"), ReadError);
}

TEST(ColumnFile, EveryRowKnowsItsLineAcrossCommentsAndBlankLines) {
  // The row-to-line map is kept as runs of consecutive lines: checked against the lines written.
  std::string text = "# run 3\ntime x\n";
  std::vector<std::size_t> expected;
  std::size_t line = 2;
  unsigned state = 12345;
  for (int row = 0; row < 2000; ++row) {
    state = state * 1103515245u + 12345u;
    const unsigned gap = (state >> 16) % 7 == 0 ? (state >> 20) % 3 + 1 : 0;  // sometimes 1..3 lines between rows
    for (unsigned g = 0; g < gap; ++g, ++line) text += g % 2 ? "\n" : "   # note\n";
    text += std::to_string(row) + " 1\n";
    expected.push_back(++line);
  }
  const Table t = parse_column_text(text, "mem");
  ASSERT_EQ(t.rows(), expected.size());
  for (std::size_t r = 0; r < expected.size(); ++r) ASSERT_EQ(t.line_of(r), expected[r]) << "row " << r;
  EXPECT_EQ(t.where(1999), "mem:" + std::to_string(expected.back()));
  EXPECT_EQ(t.where(2000), "mem");
}

TEST(ColumnFile, FilesThatAreNotTextAreSaidForWhatTheyAre) {
  // A binary file read as rows of numbers failed on some line with a column count that meant
  // nothing; the first bytes say what it is (and gzip is looked through first).
  namespace fs = std::filesystem;
  const fs::path dir = fs::temp_directory_path() / ("mlce_binary_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  auto error_reading = [&](const std::string& name, const std::string& bytes) {
    std::ofstream(dir / name, std::ios::binary) << bytes;
    try {
      read_column_file((dir / name).string());
    } catch (const ReadError& e) {
      return std::string(e.what());
    }
    return std::string("read");
  };
  const std::string u16 = (dir / "series.txt").string();
  EXPECT_EQ(error_reading("series.txt", std::string("\xFF\xFE" "0\0 \0" "1\0\n\0", 10)),
            u16 + ": UTF-16 text (a spreadsheet's \"Unicode text\"): save it as \"CSV UTF-8\", or convert it: iconv -f "
                  "UTF-16 -t UTF-8 " + u16 + " > series-utf8.txt");
  EXPECT_EQ(error_reading("run.dat", std::string("CDF\x01\0\0\0\x05", 8)),
            (dir / "run.dat").string() + ": NetCDF (or HDF5) data where text was expected: the NetCDF reader takes it as a "
                                         "file of its own (name the file, not a pipe or a member of a text output set)");
  EXPECT_EQ(error_reading("run.h5", "\x89HDF\r\n\x1A\n"),
            (dir / "run.h5").string() + ": NetCDF (or HDF5) data where text was expected: the NetCDF reader takes it as a "
                                        "file of its own (name the file, not a pipe or a member of a text output set)");
  EXPECT_EQ(error_reading("x.mat", std::string("MATLAB 5.0 MAT-file, Platform: GLNXA64\0\0", 40)),
            (dir / "x.mat").string() + ": a MATLAB MAT-file (binary): write the series as text, e.g. writematrix([t x], 'series.csv')");
  EXPECT_EQ(error_reading("a.out", std::string("1 2\n\x7F" "ELF\0\x01", 10)),
            (dir / "a.out").string() + ": binary data, not text (a zero byte at offset 8; UTF-16 text without a byte-order mark looks so too)");
  fs::remove_all(dir);
}
