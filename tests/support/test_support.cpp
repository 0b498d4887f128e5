// Test helpers shared by the unit, validation and extreme tests.
