// The source FMU: what an FMU's sources/ holds, with buildDescription.xml,
// builds its shared object again. The test reads buildDescription.xml as an
// importer on another platform would (validated against the FMI 3.0 build
// description schema fmusim carries), compiles every source it lists with
// its language, definitions and include directories, links the libraries it
// names, puts the new shared object in place of the FMU's own, and runs the
// rebuilt FMU under fmusim against the example's own simulator.
#include <libxml/parser.h>
#include <libxml/tree.h>
#include <libxml/xmlschemas.h>
#include <unistd.h>

#include <cstdarg>

#include "fmi_support.hpp"

#ifdef MBGC_BUILD_DESCRIPTION_SCHEMA
#include "fmi3BuildDescriptionSchema.h"  // the schema as a byte array (fmusim's sources)
#endif

namespace {

using namespace fmi_test;

struct Library {
  std::string name;
  bool versioned = false;  ///< a version given: a library to link, not headers only
};

struct BuildDescription {
  std::string model_identifier, language;
  std::vector<std::string> sources, include_directories, definitions;  ///< definitions as NAME=VALUE
  std::vector<Library> libraries;
  std::string schema_errors;  ///< empty when it validates
};

std::string attribute(xmlNode* node, const char* name) {
  xmlChar* value = xmlGetProp(node, reinterpret_cast<const xmlChar*>(name));
  std::string out = value ? reinterpret_cast<const char*>(value) : "";
  xmlFree(value);
  return out;
}

bool named(xmlNode* node, const char* name) {
  return node->type == XML_ELEMENT_NODE && std::string(reinterpret_cast<const char*>(node->name)) == name;
}

#ifdef MBGC_BUILD_DESCRIPTION_SCHEMA
void collect_error(void* context, const char* format, ...) {
  char text[1024];
  va_list args;
  va_start(args, format);
  std::vsnprintf(text, sizeof text, format, args);
  va_end(args);
  *static_cast<std::string*>(context) += text;
}
#endif

BuildDescription read_build_description(const std::string& path) {
  BuildDescription d;
  xmlDoc* doc = xmlReadFile(path.c_str(), nullptr, XML_PARSE_NONET);
  if (!doc) {
    d.schema_errors = "not XML";
    return d;
  }
#ifdef MBGC_BUILD_DESCRIPTION_SCHEMA
  xmlSchemaParserCtxt* parser = xmlSchemaNewMemParserCtxt(reinterpret_cast<const char*>(fmi3BuildDescriptionMerged_xsd),
                                                          static_cast<int>(fmi3BuildDescriptionMerged_xsd_len));
  xmlSchema* schema = xmlSchemaParse(parser);
  xmlSchemaValidCtxt* validator = xmlSchemaNewValidCtxt(schema);
  xmlSchemaSetValidErrors(validator, collect_error, collect_error, &d.schema_errors);
  if (xmlSchemaValidateDoc(validator, doc) != 0 && d.schema_errors.empty()) d.schema_errors = "invalid";
  xmlSchemaFreeValidCtxt(validator);
  xmlSchemaFree(schema);
  xmlSchemaFreeParserCtxt(parser);
#else
  std::printf("buildDescription.xml not validated: fmusim's sources (its schema) are not beside the tree\n");
#endif
  for (xmlNode* config = xmlDocGetRootElement(doc)->children; config; config = config->next) {
    if (!named(config, "BuildConfiguration")) continue;
    d.model_identifier = attribute(config, "modelIdentifier");
    for (xmlNode* part = config->children; part; part = part->next) {
      if (named(part, "Library")) d.libraries.push_back({attribute(part, "name"), !attribute(part, "version").empty()});
      if (!named(part, "SourceFileSet")) continue;
      d.language = attribute(part, "language");
      for (xmlNode* item = part->children; item; item = item->next) {
        if (named(item, "SourceFile")) d.sources.push_back(attribute(item, "name"));
        if (named(item, "IncludeDirectory")) d.include_directories.push_back(attribute(item, "name"));
        if (named(item, "PreprocessorDefinition"))
          d.definitions.push_back(attribute(item, "name") + "=" + attribute(item, "value"));
      }
    }
  }
  xmlFreeDoc(doc);
  return d;
}

TEST(SourceFmu, BuildsAgainFromItsSourcesAndBuildDescription) {
  const std::string dir = work("source_fmu." + std::to_string(::getpid()));
  const std::string unpacked = dir + "/fmu", sources = unpacked + "/sources";
  ASSERT_EQ(shell("rm -rf '" + dir + "' && mkdir -p '" + unpacked + "' && cd '" + unpacked + "' && unzip -q '" +
                  fmu_of("bouncing_ball", 3) + "'"),
            0);
  const BuildDescription d = read_build_description(sources + "/buildDescription.xml");
  EXPECT_EQ(d.schema_errors, "");
  ASSERT_EQ(d.model_identifier, "bouncing_ball");
  ASSERT_EQ(d.language, "C++20");
  ASSERT_FALSE(d.sources.empty());

  // The FMU's own binary goes: only what the sources build is left to run.
  const std::string binary = unpacked + "/binaries/x86_64-linux/" + d.model_identifier + ".so";
  ASSERT_EQ(std::remove(binary.c_str()), 0);
  std::string flags = "-std=c++20 -O0 -fPIC -fvisibility=hidden";  // (-O0: the quickest to compile)
  for (const std::string& definition : d.definitions) flags += " -D" + definition;
  for (const std::string& include : d.include_directories) flags += " -I'" + sources + "/" + include + "'";
  std::string link;
  for (const Library& library : d.libraries) {
    // Debian: SUNDIALS' libraries are linked, the header-only ones are found by pkg-config
    if (library.versioned) link += " -l" + library.name;
    else if (shell("pkg-config --exists " + library.name) == 0) flags += " $(pkg-config --cflags " + library.name + ")";
  }
  // each source compiled on its own, two at a time (the machines have 2 cores)
  std::string commands;
  for (const std::string& source : d.sources) {
    EXPECT_EQ(access((sources + "/" + source).c_str(), R_OK), 0) << source << " is listed but not in sources/";
    std::string object = source;
    std::replace(object.begin(), object.end(), '/', '_');
    commands += std::string(CXX_COMPILER) + " " + flags + " -c '" + sources + "/" + source + "' -o '" + dir + "/obj/" +
                object + ".o'\n";
  }
  const std::string log = dir + "/build.log";
  std::ofstream(dir + "/commands.txt") << commands;
  ASSERT_EQ(shell("mkdir -p '" + dir + "/obj' && xargs -d '\\n' -n 1 -P 2 sh -c < '" + dir + "/commands.txt' > '" +
                  log + "' 2>&1"),
            0)
      << slurp(log);
  ASSERT_EQ(shell(std::string(CXX_COMPILER) + " -shared -o '" + binary + "' '" + dir + "'/obj/*.o" + link +
                  " -Wl,--no-undefined > '" + log + "' 2>&1"),
            0)
      << slurp(log);
  ASSERT_EQ(shell("cd '" + unpacked + "' && zip -qr ../rebuilt.fmu ."), 0);

  const Table reference = native(SIM_BOUNCING_BALL, "source_fmu");
  const Table cs = imported(dir + "/rebuilt.fmu", "source_fmu.cs", "--interface-type cs");
  ASSERT_FALSE(reference.rows.empty());
  ASSERT_EQ(cs.rows.size(), reference.rows.size());
  std::string where;
  const double worst = worst_difference(reference, cs, where);
  std::printf("bouncing_ball rebuilt from its sources, co-simulation: %.2g of scale (%s)\n", worst, where.c_str());
  EXPECT_LE(worst, 1e-9) << where;
  shell("rm -rf '" + dir + "'");
}

}  // namespace
