// Particle selection (particles.h: parseSelection, applySelection; the CLI's
// --select): the grammar, good and bad expressions, and the filtering, which
// drops particles from the positions and every attribute alike.
#include <cmath>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "meniscus/particles.h"

namespace meniscus::select_test_local {
namespace {

ParticleFilter parsed(const std::string& text) {
    auto f = parseSelection(text);
    EXPECT_TRUE(f.ok()) << text << ": " << (f.ok() ? "" : f.error().describe());
    return f.ok() ? *f : ParticleFilter{};
}

void expectParseError(const std::string& text, const std::string& word) {
    auto f = parseSelection(text);
    ASSERT_FALSE(f.ok()) << "'" << text << "' parsed";
    const std::string m = f.error().describe();
    EXPECT_NE(m.find("--select"), std::string::npos) << m;
    EXPECT_NE(m.find(word), std::string::npos) << "expected '" << word << "' in: " << m;
}

// ---------------------------------------------------------------- parsing

TEST(SelectParse, ClausesOperatorsAndValues) {
    const ParticleFilter f = parsed(" density > 900 && velocity.y<=-0.5&&id!=7 && |velocity| >= 2e0 && x<1 && z==3 ");
    ASSERT_EQ(f.clauses.size(), 6u);
    EXPECT_EQ(f.text, "density > 900 && velocity.y<=-0.5&&id!=7 && |velocity| >= 2e0 && x<1 && z==3");
    EXPECT_EQ(f.clauses[0].attribute, "density");
    EXPECT_EQ(f.clauses[0].op, SelectOp::Greater);
    EXPECT_EQ(f.clauses[0].low, 900.0);
    EXPECT_EQ(f.clauses[0].text, "density > 900");
    EXPECT_EQ(f.clauses[1].attribute, "velocity.y");
    EXPECT_EQ(f.clauses[1].op, SelectOp::LessEqual);
    EXPECT_EQ(f.clauses[1].low, -0.5);
    EXPECT_EQ(f.clauses[2].op, SelectOp::NotEqual);
    EXPECT_TRUE(f.clauses[3].magnitude);
    EXPECT_EQ(f.clauses[3].attribute, "velocity");
    EXPECT_EQ(f.clauses[3].op, SelectOp::GreaterEqual);
    EXPECT_EQ(f.clauses[4].op, SelectOp::Less);
    EXPECT_EQ(f.clauses[5].op, SelectOp::Equal);
    EXPECT_TRUE(parsed("").empty());
    EXPECT_TRUE(parsed("   ").empty());
}

TEST(SelectParse, DualSphysicsTypeNames) {
    auto one = [](const std::string& text) { return parsed(text).clauses.at(0); };
    EXPECT_EQ(one("Type==fluid").low, 3.0);
    EXPECT_EQ(one("Type==fluid").high, 3.0);
    EXPECT_EQ(one("type == FIXED").low, 0.0);
    EXPECT_EQ(one("Type!=moving").low, 1.0);
    EXPECT_EQ(one("Type==floating").low, 2.0);
    EXPECT_EQ(one("Type<fluid").op, SelectOp::Less);
    const SelectClause bound = one("Type==bound");
    EXPECT_EQ(bound.low, 0.0);
    EXPECT_EQ(bound.high, 2.0);
    EXPECT_EQ(one("Type!=boundary").high, 2.0);
    EXPECT_EQ(one("Type==3").low, 3.0);
}

TEST(SelectParse, BadExpressionsSayWhy) {
    expectParseError("density", "operator");
    expectParseError("density=900", "==");
    expectParseError("density>", "value");
    expectParseError("density>heavy", "not a number");
    expectParseError("density>1e999", "not a number");
    expectParseError("Type==water", "fluid (3)");
    expectParseError("density==fluid", "Type");
    expectParseError("Type<bound", "== or !=");
    expectParseError("density>1 || Type==fluid", "&&");
    expectParseError("density>1 &&", "empty clause");
    expectParseError("density>1 & x<2", "&&");
    expectParseError("|velocity>2", "closing");
    expectParseError("900<density", "attribute name");
}

// ---------------------------------------------------------------- filtering

// Six particles: type 0 0 1 2 3 3 (DualSPHysics' codes), each attribute distinct.
ParticleSet tank() {
    ParticleSet set;
    for (int i = 0; i < 6; ++i) set.positions.emplace_back(float(i), 0.5f * float(i), -float(i));
    Attribute id{"id", AttributeType::Int, 1, {}, {10, 11, 12, 13, 14, 15}};
    Attribute vel{"velocity", AttributeType::Float, 3, {0, 0, 0, 1, 0, 0, 0, -1, 0, 0, 3, 0, 2, -2, 0, 0, 0.5f, 0}, {}};
    Attribute rho{"density", AttributeType::Float, 1, {1000, 1001, 0.1f, 950, 899, NAN}, {}};
    Attribute type{"Type", AttributeType::Float, 1, {0, 0, 1, 2, 3, 3}, {}};
    Attribute mk{"Mk", AttributeType::Int, 2, {}, {0, 1, 0, 1, 10, 11, 50, 51, 1, 1, 1, 2}};
    set.attributes = {id, vel, rho, type, mk};
    return set;
}

std::vector<std::int64_t> ids(const ParticleSet& set) { return set.find("id")->ints; }

ParticleSet selected(const std::string& text) {
    ParticleSet set = tank();
    Status st = applySelection(set, parsed(text), "tank.csv");
    EXPECT_TRUE(st.ok()) << text << ": " << (st.ok() ? "" : st.error().describe());
    return set;
}

TEST(SelectApply, EveryAttributeFilteredAlike) {
    const ParticleSet s = selected("Type==fluid");
    ASSERT_EQ(s.size(), 2u);
    EXPECT_EQ(s.positions[0], glm::vec3(4, 2, -4));
    EXPECT_EQ(s.positions[1], glm::vec3(5, 2.5f, -5));
    EXPECT_EQ(ids(s), (std::vector<std::int64_t>{14, 15}));
    EXPECT_EQ(s.find("velocity")->floats, (std::vector<float>{2, -2, 0, 0, 0.5f, 0}));
    EXPECT_EQ(s.find("density")->floats[0], 899.0f);
    EXPECT_TRUE(std::isnan(s.find("density")->floats[1]));
    EXPECT_EQ(s.find("Type")->floats, (std::vector<float>{3, 3}));
    EXPECT_EQ(s.find("Mk")->ints, (std::vector<std::int64_t>{1, 1, 1, 2}));
    EXPECT_EQ(s.attributes.size(), 5u);
}

TEST(SelectApply, ClausesAndOperators) {
    EXPECT_EQ(ids(selected("Type==bound")), (std::vector<std::int64_t>{10, 11, 12, 13}));
    EXPECT_EQ(ids(selected("Type!=bound")), (std::vector<std::int64_t>{14, 15}));
    EXPECT_EQ(ids(selected("type==moving")), (std::vector<std::int64_t>{12}));  // any case
    EXPECT_EQ(ids(selected("id>=13 && id<15")), (std::vector<std::int64_t>{13, 14}));
    EXPECT_EQ(ids(selected("velocity.y<0")), (std::vector<std::int64_t>{12, 14}));
    EXPECT_EQ(ids(selected("velocity.0>0.5")), (std::vector<std::int64_t>{11, 14}));
    EXPECT_EQ(ids(selected("|velocity|>2")), (std::vector<std::int64_t>{13, 14}));  // 3 and 2.83
    EXPECT_EQ(ids(selected("x>3.5")), (std::vector<std::int64_t>{14, 15}));
    EXPECT_EQ(ids(selected("position.z>=-1")), (std::vector<std::int64_t>{10, 11}));
    EXPECT_EQ(ids(selected("|position.z|<1")), (std::vector<std::int64_t>{10}));
    EXPECT_EQ(ids(selected("Mk.x>=1 && Type<=2")), (std::vector<std::int64_t>{12, 13}));
}

TEST(SelectApply, FloatPrecisionAndNaN) {
    // 0.1 is compared as the float it was stored as.
    EXPECT_EQ(ids(selected("density==0.1")), (std::vector<std::int64_t>{12}));
    // NaN matches only !=.
    EXPECT_EQ(ids(selected("density<2000")), (std::vector<std::int64_t>{10, 11, 12, 13, 14}));
    EXPECT_EQ(ids(selected("density!=1000")), (std::vector<std::int64_t>{11, 12, 13, 14, 15}));
}

TEST(SelectApply, EmptyFilterChangesNothing) {
    ParticleSet set = tank();
    ASSERT_TRUE(applySelection(set, ParticleFilter{}, "tank.csv").ok());
    EXPECT_EQ(set.size(), 6u);
}

void expectApplyError(const std::string& text, const std::vector<std::string>& words) {
    ParticleSet set = tank();
    Status st = applySelection(set, parsed(text), "tank.csv");
    ASSERT_FALSE(st.ok()) << text;
    const std::string m = st.error().describe();
    EXPECT_EQ(m.rfind("tank.csv: --select '", 0), 0u) << m;
    for (const std::string& w : words) EXPECT_NE(m.find(w), std::string::npos) << "expected '" << w << "' in: " << m;
    EXPECT_EQ(set.size(), 6u) << "an error leaves the set whole";
    EXPECT_EQ(set.find("velocity")->floats.size(), 18u);
}

TEST(SelectApply, ErrorsNameTheFileAndTheProblem) {
    expectApplyError("Tpye==3", {"no attribute 'Tpye'", "Type", "density", "velocity (3)"});
    expectApplyError("velocity>1", {"3 components", "velocity.x", "|velocity|"});
    expectApplyError("density.y>1", {"1 component"});
    expectApplyError("velocity.w>1", {"no attribute 'velocity.w'"});
    expectApplyError("position>1", {"position.x", "|position|"});
    expectApplyError("Type==fluid && density>2000", {"no particle matches", "of 6"});
}

TEST(SelectApply, InconsistentAttributeIsAnError) {
    ParticleSet set = tank();
    set.find("Mk")->ints.pop_back();
    Status st = applySelection(set, parsed("Type==fluid"), "bad.csv");
    ASSERT_FALSE(st.ok());
    EXPECT_NE(st.error().describe().find("'Mk'"), std::string::npos) << st.error().describe();
    EXPECT_EQ(set.size(), 6u);
}

}  // namespace
}  // namespace meniscus::select_test_local
