"""Contacts: the contact model every producer and report shares (usdksl/README.md, Floors: floor 1).

One concept per module: ``table`` holds the contact table and puts rows in canonical order
(:func:`~usdksl.contacts.table.canonical_first_contacts`), ``orientation`` says which side of a face pair
is side a, ``csv_file`` reads and writes contacts.csv, ``baseline`` holds contacts accepted earlier
against a check. None of them reads USD.
"""
