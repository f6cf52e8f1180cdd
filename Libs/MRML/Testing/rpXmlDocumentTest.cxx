// rp::ParseXml / ReadXmlFile: elements, attributes and entities as expat decodes them, and the
// line of a malformed document named in the error.
#include <gtest/gtest.h>

#include <cstdio>
#include <fstream>

#include <vtkXMLDataElement.h>

#include "rpXmlDocument.h"

TEST(XmlDocument, ReadsNestedElementsAndDecodesEntitiesInAttributes) {
  std::string error;
  auto root = rp::ParseXml("<?xml version=\"1.0\"?>\n<MRML version=\"Slicer4\">\n"
                           "  <Volume id=\"vtkMRMLScalarVolumeNode1\" name=\"CT &amp; MR\"/>\n</MRML>\n",
                           "scene.mrml", error);
  ASSERT_TRUE(root) << error;
  EXPECT_STREQ(root->GetName(), "MRML");
  ASSERT_EQ(root->GetNumberOfNestedElements(), 1);
  EXPECT_STREQ(root->GetNestedElement(0)->GetAttribute("name"), "CT & MR");
}

TEST(XmlDocument, NamesTheLineOfAMismatchedTag) {
  std::string error;
  auto root = rp::ParseXml("<A>\n<B>\n</C>\n</A>\n", "bad.xml", error);
  EXPECT_FALSE(root);
  EXPECT_NE(error.find("bad.xml: malformed XML at line 3"), std::string::npos) << error;
}

TEST(XmlDocument, RefusesAnEmptyDocumentAndAMissingFile) {
  std::string error;
  EXPECT_FALSE(rp::ParseXml("  \n", "empty.xml", error));
  EXPECT_NE(error.find("empty.xml: empty document"), std::string::npos) << error;
  EXPECT_FALSE(rp::ReadXmlFile("/nonexistent/dir/x.xml", error));
  EXPECT_NE(error.find("/nonexistent/dir/x.xml: cannot open"), std::string::npos) << error;
}

TEST(XmlDocument, RefusesAFileOverTheSizeLimit) {
  const std::string path = testing::TempDir() + "/big.xml";
  std::ofstream(path) << "<A>" << std::string(2000, ' ') << "</A>";
  std::string error;
  EXPECT_FALSE(rp::ReadXmlFile(path, error, 1000));
  EXPECT_NE(error.find("more than the 1000"), std::string::npos) << error;
  EXPECT_TRUE(rp::ReadXmlFile(path, error)) << error;
  std::remove(path.c_str());
}
