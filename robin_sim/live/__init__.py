"""The live page: a person in the loop through a browser (issue 11)."""
