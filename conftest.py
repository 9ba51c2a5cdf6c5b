# Lets the tests import aaeval from a plain checkout, without installing it.
