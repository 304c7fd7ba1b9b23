"""Reports: contacts.csv, summary.csv, JSON, JUnit, the contact timeline and the USD override layer, written atomically."""
