"""Reports: contacts.csv, summary.csv, JSON, JUnit and the USD override layer, written atomically."""
